#include "raycast/raycast_scene.h"

#include <limits>
#include <map>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

namespace vscan::raycast {
namespace {

SceneInstance MeshInstance(TriangleMesh mesh, uint32_t id) {
  SceneInstance instance;
  instance.mesh = test::Share(std::move(mesh));
  instance.instance_id = id;
  return instance;
}

TEST(RaycastSceneTest, IcosphereIsClosed) {
  const TriangleMesh sphere = test::MakeIcosphere(Eigen::Vector3d::Zero(), 1.0, 2);
  EXPECT_EQ(sphere.triangles.size(), 20u * 16u);
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : sphere.triangles) {
    for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[k], t[(k + 1) % 3])];
  }
  for (const auto& [edge, faces] : edges) EXPECT_EQ(faces, 2);
}

TEST(RaycastSceneTest, CountsTrianglesAndMapsGeometriesToInstances) {
  std::vector<SceneInstance> instances = {
      MeshInstance(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0), 7),
      MeshInstance(test::MakeIcosphere(Eigen::Vector3d(3, 0, 0), 1.0, 1), 42)};
  auto scene = RaycastScene::Build(instances);
  ASSERT_TRUE(scene.ok()) << scene.status().ToString();
  EXPECT_EQ((*scene)->triangle_count(), 2u + 80u);
  EXPECT_EQ((*scene)->InstanceOfGeometry(0), 7u);
  EXPECT_EQ((*scene)->InstanceOfGeometry(1), 42u);
  EXPECT_EQ((*scene)->InstanceOfGeometry(99), 0u);
}

TEST(RaycastSceneTest, EmptySceneBuilds) {
  auto scene = RaycastScene::Build({});
  ASSERT_TRUE(scene.ok()) << scene.status().ToString();
  EXPECT_EQ((*scene)->triangle_count(), 0u);
}

TEST(RaycastSceneTest, RejectsNonFiniteVertices) {
  TriangleMesh mesh = test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0);
  mesh.vertices[2].y() = std::numeric_limits<float>::quiet_NaN();
  const std::vector<SceneInstance> instances = {MeshInstance(std::move(mesh), 1)};
  auto scene = RaycastScene::Build(instances);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(scene.status().message().find("instances[0]"), std::string::npos) << scene.status().message();
}

TEST(RaycastSceneTest, RejectsOutOfRangeIndices) {
  TriangleMesh mesh = test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0);
  mesh.triangles[1][2] = 4;
  const std::vector<SceneInstance> instances = {
      MeshInstance(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0), 1),
      MeshInstance(std::move(mesh), 2)};
  auto scene = RaycastScene::Build(instances);
  ASSERT_FALSE(scene.ok());
  EXPECT_EQ(scene.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(scene.status().message().find("instances[1].mesh.triangles[1]"), std::string::npos)
      << scene.status().message();
}

TEST(RaycastSceneTest, RejectsMissingMeshBadScaleAndNonFinitePose) {
  SceneInstance missing;
  EXPECT_EQ(RaycastScene::Build(std::vector<SceneInstance>{missing}).status().code(), StatusCode::kInvalidArgument);

  SceneInstance scaled = MeshInstance(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0), 1);
  scaled.scale = 0;
  EXPECT_EQ(RaycastScene::Build(std::vector<SceneInstance>{scaled}).status().code(), StatusCode::kInvalidArgument);

  SceneInstance posed = MeshInstance(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0), 1);
  posed.world_from_object.translation().x() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(RaycastScene::Build(std::vector<SceneInstance>{posed}).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vscan::raycast
