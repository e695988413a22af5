// The web view's read-only API over a real catalogue: who gets data, what the JSON and the mesh
// bytes hold, and what is refused.

#include "web/web_api.h"

#include <cstring>

#include <gtest/gtest.h>

#include "scenes/scene_registry.h"
#include "sensor/material.h"
#include "store/blob_store.h"
#include "vscan_test/temp_dir.h"

namespace vscan::web {
namespace {

constexpr std::string_view kTriangleObj = "v 0 0 0\nv 0.5 0 0\nv 0 0.25 0\nf 1 2 3\n";

class WebApiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto catalogue = store::Catalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(catalogue.ok());
    catalogue_ = std::move(catalogue).value();
    blobs_ = std::make_unique<store::BlobStore>(dir_.path() / "blobs");
    ASSERT_TRUE(blobs_->Open().ok());
    registry_ = std::make_unique<scenes::SceneRegistry>(*catalogue_, *blobs_);
    scenes::MeshUpload upload;
    upload.name = "tri.obj";
    upload.format = geometry::MeshFileFormat::kObj;
    upload.unit = store::LengthUnit::kMetre;
    auto mesh = registry_->AddMesh(kTriangleObj, upload);
    ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
    mesh_id_ = mesh->mesh_id;
    auto scene = catalogue_->CreateScene("say \"hi\"\n<b>");
    ASSERT_TRUE(scene.ok());
    scene_id_ = scene->scene_id;
    store::ObjectRecord object;
    object.scene_id = scene_id_;
    object.mesh_id = mesh_id_;
    object.pose(0, 3) = 1.5;
    object.label = "part";
    auto added = catalogue_->AddObject(object);
    ASSERT_TRUE(added.ok());
    object_id_ = added->first.object_id;
  }

  WebApi Api(uint64_t max_triangles = 1000) {
    return WebApi(WebSources{.scenes = registry_.get()}, WebApiOptions{.token = "s3cret", .max_mesh_triangles = max_triangles});
  }

  test::TempDir dir_;
  std::unique_ptr<store::Catalogue> catalogue_;
  std::unique_ptr<store::BlobStore> blobs_;
  std::unique_ptr<scenes::SceneRegistry> registry_;
  std::string mesh_id_, scene_id_, object_id_;
};

TEST_F(WebApiTest, OnlyTheBearerTokenGetsData) {
  const WebApi api = Api();
  for (const char* header : {"", "s3cret", "Bearer", "Bearer ", "Bearer s3cre", "Bearer s3cretx", "Basic s3cret",
                             "Bearer  s3cret"}) {
    const WebReply reply = api.Handle("GET", "/api/scenes", "", header);
    EXPECT_EQ(reply.status, 401) << header;
    EXPECT_EQ(reply.body.find(scene_id_), std::string::npos) << header;
  }
  // The scheme is case-insensitive (RFC 9110); the token is not.
  EXPECT_EQ(api.Handle("GET", "/api/scenes", "", "Bearer s3cret").status, 200);
  EXPECT_EQ(api.Handle("GET", "/api/scenes", "", "bearer s3cret").status, 200);
  EXPECT_EQ(api.Handle("GET", "/api/scenes", "", "Bearer S3CRET").status, 401);
  // A server without a token serves anyone.
  const WebApi open(WebSources{.scenes = registry_.get()}, WebApiOptions{});
  EXPECT_EQ(open.Handle("GET", "/api/scenes", "", "").status, 200);
}

TEST_F(WebApiTest, OnlyGetIsServed) {
  const WebApi api = Api();
  for (const char* method : {"POST", "PUT", "DELETE", "PATCH", "HEAD"}) {
    EXPECT_EQ(api.Handle(method, "/api/scenes", "", "Bearer s3cret").status, 405) << method;
  }
}

TEST_F(WebApiTest, UnknownIdsAndPathsAreNotFound) {
  const WebApi api = Api();
  for (const std::string path : {"/api/scenes/scn_0000000000000000", "/api/meshes/msh_0000000000000000",
                                 "/api/scenes/../meshes", "/api/scenes/a/b", "/api/meshes/", "/api/other"}) {
    EXPECT_EQ(api.Handle("GET", path, "", "Bearer s3cret").status, 404) << path;
  }
}

TEST_F(WebApiTest, SceneJsonHoldsTheObjectPoseAndEffectiveMaterial) {
  const WebReply reply = Api().Handle("GET", "/api/scenes/" + scene_id_, "", "Bearer s3cret");
  ASSERT_EQ(reply.status, 200) << reply.body;
  EXPECT_EQ(reply.content_type, "application/json");
  // The name escaped for JSON (and '<' so that it cannot close a script element).
  EXPECT_NE(reply.body.find(R"("name":"say \"hi\"\n\u003cb>")"), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("\"object_id\":\"" + object_id_ + "\""), std::string::npos);
  EXPECT_NE(reply.body.find(R"("world_from_object":[[1,0,0,1.5],[0,1,0,0],[0,0,1,0],[0,0,0,1]])"),
            std::string::npos)
      << reply.body;
  // No material on the object or the mesh: the default preset's values.
  const sensor::MaterialPreset& fallback = sensor::MaterialPresets().front();
  EXPECT_NE(reply.body.find("\"material\":{\"preset\":\"" + fallback.name + "\""), std::string::npos) << reply.body;

  const WebReply list = Api().Handle("GET", "/api/scenes", "", "Bearer s3cret");
  ASSERT_EQ(list.status, 200);
  EXPECT_NE(list.body.find("\"scene_id\":\"" + scene_id_ + "\""), std::string::npos);
  EXPECT_NE(list.body.find("\"object_count\":1"), std::string::npos);
}

TEST_F(WebApiTest, ObjectsOnTheTableTurnWithIt) {
  store::TableRecord table;
  table.enabled = true;
  table.angle_deg = 90;  // about +z through the origin: (1.5, 0, 0) goes to (0, 1.5, 0)
  ASSERT_TRUE(catalogue_->SetTable(scene_id_, table).ok());
  store::ObjectRecord object;
  object.scene_id = scene_id_;
  object.mesh_id = mesh_id_;
  object.pose(0, 3) = 1.5;
  object.on_table = true;
  ASSERT_TRUE(catalogue_->AddObject(object).ok());
  const WebReply reply = Api().Handle("GET", "/api/scenes/" + scene_id_, "", "Bearer s3cret");
  ASSERT_EQ(reply.status, 200);
  // The first object stays put; the second turned a quarter (cos 90 degrees prints as 6.1e-17).
  EXPECT_NE(reply.body.find(R"("world_from_object":[[1,0,0,1.5],[0,1,0,0],[0,0,1,0],[0,0,0,1]])"),
            std::string::npos);
  EXPECT_NE(reply.body.find(R"("on_table":true)"), std::string::npos);
  const size_t turned = reply.body.find(R"("on_table":true)");
  const std::string rows = reply.body.substr(reply.body.find("world_from_object", turned));
  EXPECT_NE(rows.find(",-1,0,"), std::string::npos) << rows;  // first row: (~0, -1, 0, ~0)
  EXPECT_NE(rows.find("],[1,"), std::string::npos) << rows;  // second row: (1, ~0, 0, 1.5)
  EXPECT_NE(rows.find(",0,1.5],[0,0,1,0]"), std::string::npos) << rows;
}

TEST_F(WebApiTest, MeshBytesFollowTheLayout) {
  const WebReply reply = Api().Handle("GET", "/api/meshes/" + mesh_id_, "", "Bearer s3cret");
  ASSERT_EQ(reply.status, 200) << reply.body;
  ASSERT_EQ(reply.body.size(), 16u + 3 * 12 + 1 * 12);
  EXPECT_EQ(reply.body.substr(0, 4), "VSMH");
  uint32_t header[3];
  std::memcpy(header, reply.body.data() + 4, sizeof(header));
  EXPECT_EQ(header[0], 1u);
  EXPECT_EQ(header[1], 3u);
  EXPECT_EQ(header[2], 1u);
  float vertices[9];
  std::memcpy(vertices, reply.body.data() + 16, sizeof(vertices));
  float extent_x = 0, extent_y = 0;
  for (int v = 0; v < 3; ++v) {
    extent_x = std::max(extent_x, vertices[3 * v]);
    extent_y = std::max(extent_y, vertices[3 * v + 1]);
  }
  EXPECT_FLOAT_EQ(extent_x, 0.5f);
  EXPECT_FLOAT_EQ(extent_y, 0.25f);
  uint32_t triangle[3];
  std::memcpy(triangle, reply.body.data() + 16 + 36, sizeof(triangle));
  EXPECT_EQ(triangle[0] + triangle[1] + triangle[2], 0u + 1u + 2u);
}

TEST_F(WebApiTest, MeshesAboveTheBoundAreRefused) {
  const WebReply reply = Api(0).Handle("GET", "/api/meshes/" + mesh_id_, "", "Bearer s3cret");
  EXPECT_EQ(reply.status, 422);
  EXPECT_NE(reply.body.find("1 triangles"), std::string::npos) << reply.body;
  EXPECT_NE(reply.body.find("at most 0"), std::string::npos) << reply.body;
}

}  // namespace
}  // namespace vscan::web

namespace vscan::web {
namespace {

TEST(WebRequestTest, QueryValuesAreDecoded) {
  const WebRequest request{"GET", {"clouds"}, "max_points=1000&name=a%20b+c&flag&bad=%zz"};
  EXPECT_EQ(request.Query("max_points"), "1000");
  EXPECT_EQ(request.Query("name"), "a b c");
  EXPECT_EQ(request.Query("flag"), "");
  EXPECT_EQ(request.Query("bad"), "%zz");
  EXPECT_EQ(request.Query("missing"), std::nullopt);
}

TEST(WebRequestTest, QueryIntegersAreBoundedAndNamed) {
  const auto value = [](std::string_view query) {
    return QueryInteger(WebRequest{"GET", {"clouds"}, query}, "max_points", 7, 1, 1000);
  };
  EXPECT_EQ(*value(""), 7);
  EXPECT_EQ(*value("max_points=1000"), 1000);
  for (const char* bad : {"max_points=0", "max_points=1001", "max_points=1e3", "max_points=", "max_points=-1",
                          "max_points=99999999999999999999", "max_points=12x"}) {
    const auto refused = value(bad);
    ASSERT_FALSE(refused.ok()) << bad;
    EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(refused.status().message().find("max_points"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace vscan::web
