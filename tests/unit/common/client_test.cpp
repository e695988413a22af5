// vscan::client::Client against an in-process fake server.

#include "vscan/client/client.h"

#include <gtest/gtest.h>

#include <mutex>
#include <optional>
#include <thread>

#include <grpcpp/create_channel.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/security/server_credentials.h>
#include <grpcpp/server.h>
#include <grpcpp/server_builder.h>

#include "vscan/common/point_chunks.h"

namespace vscan::client {
namespace {

class FakeScenes final : public v1::SceneService::Service {
 public:
  std::mutex mu;
  std::string last_authorization;
  std::vector<std::string> upload_parts;  // "header" or chunk sizes
  std::string uploaded;
  v1::MeshHeader upload_header;
  v1::MoveObjectRequest last_move;

  grpc::Status CreateScene(grpc::ServerContext* ctx, const v1::CreateSceneRequest* req,
                           v1::CreateSceneResponse* resp) override {
    std::lock_guard lock(mu);
    const auto it = ctx->client_metadata().find("authorization");
    if (it != ctx->client_metadata().end()) last_authorization = std::string(it->second.data(), it->second.size());
    resp->mutable_scene()->set_scene_id("scene-1");
    resp->mutable_scene()->set_name(req->name());
    return grpc::Status::OK;
  }

  grpc::Status GetScene(grpc::ServerContext*, const v1::GetSceneRequest* req, v1::GetSceneResponse* resp) override {
    if (req->scene_id() == "slow") std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (req->scene_id() != "scene-1") {
      return {grpc::StatusCode::NOT_FOUND, "scene_id: no scene '" + req->scene_id() + "'"};
    }
    auto* scene = resp->mutable_scene();
    scene->set_scene_id("scene-1");
    auto* object = scene->add_objects();
    object->set_object_id("obj-1");
    auto* q = object->mutable_pose()->mutable_quaternion();
    q->set_qw(1);
    q->mutable_translation()->set_z(0.25);
    return grpc::Status::OK;
  }

  grpc::Status ListScenes(grpc::ServerContext*, const v1::ListScenesRequest* req,
                          v1::ListScenesResponse* resp) override {
    // Three pages: "", "p2", "p3".
    const std::string& t = req->page_token();
    const int page = t.empty() ? 0 : (t == "p2" ? 1 : 2);
    for (int i = 0; i < 2; ++i) resp->add_scenes()->set_scene_id("s" + std::to_string(page * 2 + i));
    if (page < 2) resp->set_next_page_token(page == 0 ? "p2" : "p3");
    return grpc::Status::OK;
  }

  grpc::Status UploadMesh(grpc::ServerContext*, grpc::ServerReader<v1::UploadMeshRequest>* reader,
                          v1::UploadMeshResponse* resp) override {
    std::lock_guard lock(mu);
    v1::UploadMeshRequest req;
    while (reader->Read(&req)) {
      if (req.has_header()) {
        upload_parts.push_back("header");
        upload_header = req.header();
      } else {
        upload_parts.push_back(std::to_string(req.chunk().size()));
        uploaded += req.chunk();
      }
    }
    resp->mutable_mesh()->set_mesh_id("mesh-1");
    resp->mutable_mesh()->set_name(upload_header.name());
    return grpc::Status::OK;
  }

  grpc::Status MoveObject(grpc::ServerContext*, const v1::MoveObjectRequest* req,
                          v1::MoveObjectResponse* resp) override {
    std::lock_guard lock(mu);
    last_move = *req;
    resp->mutable_object()->set_object_id(req->object_id());
    resp->set_revision(7);
    return grpc::Status::OK;
  }
};

PointCloud MakeCloud(size_t n) {
  PointCloud c;
  c.fields = kFieldsAll;
  c.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    c.positions[i] = {f, -f, 0.5f * f};
    c.normals[i] = {0, 0, 1};
    c.ranges[i] = f + 1;
    c.intensities[i] = 0.5f;
    c.instance_ids[i] = 1;
    c.pixels[i] = static_cast<uint32_t>(i);
  }
  return c;
}

class FakeScans final : public v1::ScanService::Service {
 public:
  PointCloud cloud = MakeCloud(10000);
  uint64_t announced_points = 10000;
  // Set: the statistics carry it (streamed scans announce 0 points in the header).
  std::optional<uint64_t> streamed_points;
  bool send_statistics = true;

  grpc::Status Scan(grpc::ServerContext*, const v1::ScanRequest* req,
                    grpc::ServerWriter<v1::ScanResponse>* writer) override {
    if (req->scene_id() != "scene-1") return {grpc::StatusCode::NOT_FOUND, "scene_id: unknown"};
    v1::ScanResponse msg;
    auto* header = msg.mutable_header();
    header->set_scene_id(req->scene_id());
    header->set_points(announced_points);
    header->set_rays(20000);
    for (int f = v1::POINT_FIELD_POSITION; f <= v1::POINT_FIELD_PIXEL; ++f) {
      header->add_fields(static_cast<v1::PointField>(f));
    }
    writer->Write(msg);
    const size_t per = PointsPerChunk(cloud.fields, 64 * 1024);
    uint32_t index = 0;
    for (size_t begin = 0; begin < cloud.size(); begin += per) {
      msg.Clear();
      PackChunk(cloud, begin, std::min(per, cloud.size() - begin), index++, msg.mutable_chunk());
      writer->Write(msg);
    }
    if (send_statistics) {
      msg.Clear();
      msg.mutable_statistics()->set_points(cloud.size());
      msg.mutable_statistics()->set_hit_ratio(0.5);
      if (streamed_points) msg.mutable_statistics()->set_streamed_points(*streamed_points);
      writer->Write(msg);
    }
    return grpc::Status::OK;
  }
};

class ClientTest : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::EnableDefaultHealthCheckService(true);
    grpc::ServerBuilder builder;
    int port = 0;
    builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port);
    builder.RegisterService(&scenes_);
    builder.RegisterService(&scans_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    target_ = "127.0.0.1:" + std::to_string(port);
  }
  void TearDown() override { server_->Shutdown(); }

  Client Connect(ClientOptions options = {}) {
    auto client = Client::Connect(target_, options);
    EXPECT_TRUE(client.ok());
    return std::move(client).value();
  }

  FakeScenes scenes_;
  FakeScans scans_;
  std::unique_ptr<grpc::Server> server_;
  std::string target_;
};

TEST_F(ClientTest, Health) {
  Client client = Connect();
  const auto health = client.Health();
  ASSERT_TRUE(health.ok()) << health.status().ToString();
  EXPECT_EQ(health->status(), grpc::health::v1::HealthCheckResponse::SERVING);
}

TEST_F(ClientTest, BearerTokenIsSent) {
  ClientOptions options;
  options.bearer_token = "s3cret";
  Client client = Connect(options);
  const auto scene = client.CreateScene("bench");
  ASSERT_TRUE(scene.ok()) << scene.status().ToString();
  EXPECT_EQ(scene->name(), "bench");
  EXPECT_EQ(scenes_.last_authorization, "Bearer s3cret");
}

TEST_F(ClientTest, ServerErrorsKeepTheirCode) {
  Client client = Connect();
  const auto scene = client.GetScene("nope");
  EXPECT_EQ(scene.status().code(), StatusCode::kNotFound);
  EXPECT_NE(scene.status().message().find("nope"), std::string::npos);
}

TEST_F(ClientTest, UnaryDeadline) {
  ClientOptions options;
  options.unary_timeout = std::chrono::milliseconds(50);
  Client client = Connect(options);
  EXPECT_EQ(client.GetScene("slow").status().code(), StatusCode::kDeadlineExceeded);
}

TEST_F(ClientTest, UnreachableServer) {
  auto client = Client::Connect("127.0.0.1:1");
  ASSERT_TRUE(client.ok());
  EXPECT_EQ(client->ListScenes().status().code(), StatusCode::kUnavailable);
}

TEST(ClientTlsOptions, ClientCertificateAndKeyGoTogether) {
  ClientOptions cert_only;
  cert_only.tls_client_cert_path = "/etc/hostname";
  EXPECT_EQ(Client::Connect("127.0.0.1:1", cert_only).status().code(), StatusCode::kInvalidArgument);
  ClientOptions key_only;
  key_only.tls_client_key_path = "/etc/hostname";
  EXPECT_EQ(Client::Connect("127.0.0.1:1", key_only).status().code(), StatusCode::kInvalidArgument);
}

TEST(ClientTlsOptions, UnreadableFilesFailBeforeAnyCall) {
  ClientOptions missing_key;
  missing_key.tls_client_cert_path = "/etc/hostname";
  missing_key.tls_client_key_path = "/nonexistent/client.key";
  const Status status = Client::Connect("127.0.0.1:1", missing_key).status();
  EXPECT_EQ(status.code(), StatusCode::kNotFound);
  EXPECT_NE(status.message().find("tls_client_key_path"), std::string::npos) << status.message();
  ClientOptions missing_ca;
  missing_ca.tls_root_cert_path = "/nonexistent/ca.crt";
  EXPECT_EQ(Client::Connect("127.0.0.1:1", missing_ca).status().code(), StatusCode::kNotFound);
}

TEST_F(ClientTest, ListScenesFollowsPageTokens) {
  Client client = Connect();
  const auto scenes = client.ListScenes();
  ASSERT_TRUE(scenes.ok()) << scenes.status().ToString();
  ASSERT_EQ(scenes->size(), 6u);
  EXPECT_EQ(scenes->back().scene_id(), "s5");
}

TEST_F(ClientTest, UploadSendsHeaderThenMiBChunks) {
  Client client = Connect();
  std::string bytes((5u << 20) / 2, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 31);
  MeshUploadOptions options;
  options.name = "part";
  options.format = v1::MESH_FORMAT_STL;
  options.unit = v1::LENGTH_UNIT_MILLIMETRE;
  options.scale = 2;
  std::vector<uint64_t> progress;
  const auto mesh = client.UploadMeshBytes(bytes, options, [&](uint64_t done, uint64_t total) {
    EXPECT_EQ(total, bytes.size());
    progress.push_back(done);
  });
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->name(), "part");
  EXPECT_EQ(scenes_.upload_parts, (std::vector<std::string>{"header", "1048576", "1048576", "524288"}));
  EXPECT_EQ(scenes_.upload_header.size_bytes(), bytes.size());
  EXPECT_EQ(scenes_.upload_header.unit(), v1::LENGTH_UNIT_MILLIMETRE);
  EXPECT_EQ(scenes_.upload_header.format(), v1::MESH_FORMAT_STL);
  EXPECT_EQ(scenes_.upload_header.scale(), 2);
  EXPECT_EQ(scenes_.uploaded, bytes);
  EXPECT_EQ(progress.back(), bytes.size());
}

TEST_F(ClientTest, UploadFileInfersFormatAndName) {
  Client client = Connect();
  MeshUploadOptions options;
  options.unit = v1::LENGTH_UNIT_METRE;
  const auto mesh = client.UploadMeshFile(std::string(VSCAN_DATA_DIR) + "/parts/round.stl", options);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(scenes_.upload_header.format(), v1::MESH_FORMAT_STL);
  EXPECT_EQ(scenes_.upload_header.name(), "round.stl");
  EXPECT_EQ(scenes_.uploaded.size(), scenes_.upload_header.size_bytes());
  EXPECT_EQ(client.UploadMeshFile("/nonexistent/x.stl", options).status().code(), StatusCode::kNotFound);
}

TEST_F(ClientTest, MoveWithoutPoseKeepsCurrentPose) {
  Client client = Connect();
  const auto moved = client.MoveObject("scene-1", "obj-1", std::nullopt, 3.0);
  ASSERT_TRUE(moved.ok()) << moved.status().ToString();
  EXPECT_EQ(moved->revision(), 7u);
  EXPECT_EQ(scenes_.last_move.scale(), 3.0);
  EXPECT_EQ(scenes_.last_move.pose().quaternion().translation().z(), 0.25);
  EXPECT_EQ(client.MoveObject("scene-1", "obj-9", std::nullopt, 2.0).status().code(), StatusCode::kNotFound);
}

TEST_F(ClientTest, ScanAssemblesChunks) {
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  int headers = 0;
  uint64_t last = 0;
  ScanCallbacks callbacks;
  callbacks.on_header = [&](const v1::ScanHeader& h) {
    ++headers;
    EXPECT_EQ(h.points(), 10000u);
  };
  callbacks.on_progress = [&](uint64_t done, uint64_t total) {
    EXPECT_GT(done, last);
    EXPECT_EQ(total, 10000u);
    last = done;
  };
  const auto result = client.Scan(request, callbacks);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(headers, 1);
  EXPECT_EQ(last, 10000u);
  EXPECT_EQ(result->cloud.fields, static_cast<uint32_t>(kFieldsAll));
  EXPECT_EQ(result->cloud.positions, scans_.cloud.positions);
  EXPECT_EQ(result->cloud.pixels, scans_.cloud.pixels);
  EXPECT_EQ(result->cloud.ranges, scans_.cloud.ranges);
  EXPECT_EQ(result->stats.hit_ratio(), 0.5);
}

TEST_F(ClientTest, StreamedScanWithoutCountsLandsInArraysReservedForEveryRay) {
  scans_.announced_points = 0;
  scans_.streamed_points = 10000;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  uint64_t last = 0;
  ScanCallbacks callbacks;
  callbacks.on_progress = [&](uint64_t done, uint64_t total) {
    EXPECT_EQ(total, 0u);
    last = done;
  };
  const auto result = client.Scan(request, callbacks);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(last, 10000u);
  EXPECT_EQ(result->cloud.positions, scans_.cloud.positions);
  EXPECT_EQ(result->cloud.instance_ids, scans_.cloud.instance_ids);
  // The header's 20000 rays: no array grew (and copied itself) along the way.
  EXPECT_GE(result->cloud.positions.capacity(), 20000u);
  EXPECT_GE(result->cloud.pixels.capacity(), 20000u);
}

TEST_F(ClientTest, ChunksGoToOnChunkInsteadOfTheCloud) {
  scans_.announced_points = 0;
  scans_.streamed_points = 10000;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  PointCloud received;
  received.fields = kFieldsAll;
  uint64_t last = 0;
  ScanCallbacks callbacks;
  callbacks.on_chunk = [&](const v1::PointChunk& chunk) { return AppendChunk(chunk, &received); };
  callbacks.on_progress = [&](uint64_t done, uint64_t) { last = done; };
  const auto result = client.Scan(request, callbacks);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(last, 10000u);
  EXPECT_EQ(result->cloud.size(), 0u);
  EXPECT_EQ(result->cloud.positions.capacity(), 0u);
  EXPECT_EQ(received.positions, scans_.cloud.positions);
  EXPECT_EQ(received.pixels, scans_.cloud.pixels);
}

TEST_F(ClientTest, AnOnChunkErrorStopsTheScanWithIt) {
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  int chunks = 0;
  ScanCallbacks callbacks;
  callbacks.on_chunk = [&](const v1::PointChunk&) {
    ++chunks;
    return DataLoss("disk full");
  };
  const auto result = client.Scan(request, callbacks);
  EXPECT_EQ(result.status().code(), StatusCode::kDataLoss);
  EXPECT_EQ(result.status().message(), "disk full");
  EXPECT_EQ(chunks, 1);
}

TEST_F(ClientTest, StreamedScanShortOfItsStatisticsIsDataLoss) {
  scans_.announced_points = 0;
  scans_.streamed_points = 10001;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  const auto result = client.Scan(request);
  EXPECT_EQ(result.status().code(), StatusCode::kDataLoss);
  EXPECT_NE(result.status().message().find("received 10000 of 10001 points"), std::string::npos);
}

TEST_F(ClientTest, ScanWithFewerPointsThanAnnouncedIsDataLoss) {
  scans_.announced_points = 20000;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  EXPECT_EQ(client.Scan(request).status().code(), StatusCode::kDataLoss);
}

TEST_F(ClientTest, ScanWithMorePointsThanAnnouncedIsDataLoss) {
  scans_.announced_points = 100;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  EXPECT_EQ(client.Scan(request).status().code(), StatusCode::kDataLoss);
}

TEST_F(ClientTest, ScanWithoutStatisticsIsDataLoss) {
  scans_.send_statistics = false;
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("scene-1");
  EXPECT_EQ(client.Scan(request).status().code(), StatusCode::kDataLoss);
}

TEST_F(ClientTest, ScanErrorFromServer) {
  Client client = Connect();
  v1::ScanRequest request;
  request.set_scene_id("other");
  EXPECT_EQ(client.Scan(request).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace vscan::client
