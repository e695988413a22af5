#include "raycast/point_queries.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "vscan_test/mesh_distance.h"
#include "vscan_test/meshes.h"

namespace vscan::raycast {
namespace {

std::shared_ptr<const RaycastScene> SceneOf(TriangleMesh mesh) {
  SceneInstance instance;
  instance.mesh = test::Share(std::move(mesh));
  auto scene = RaycastScene::Build(std::span<const SceneInstance>(&instance, 1));
  EXPECT_TRUE(scene.ok());
  return *scene;
}

TEST(ClosestPointOnTriangle, FaceEdgeAndVertexRegions) {
  const Eigen::Vector3f a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(ClosestPointOnTriangle({0.2f, 0.3f, 0.5f}, a, b, c).isApprox(Eigen::Vector3f(0.2f, 0.3f, 0)));
  EXPECT_TRUE(ClosestPointOnTriangle({0.5f, -1, 0}, a, b, c).isApprox(Eigen::Vector3f(0.5f, 0, 0)));
  EXPECT_TRUE(ClosestPointOnTriangle({-1, -1, 2}, a, b, c).isApprox(a));
  EXPECT_TRUE(ClosestPointOnTriangle({2, -0.5f, 0}, a, b, c).isApprox(b));
  EXPECT_TRUE(ClosestPointOnTriangle({1, 1, 0}, a, b, c).isApprox(Eigen::Vector3f(0.5f, 0.5f, 0)));
}

TEST(DistancesToSurface, MatchesBruteForceOnASphere) {
  const TriangleMesh sphere = test::MakeIcosphere(Eigen::Vector3d(0.1, -0.2, 0.3), 0.5, 2);
  const auto scene = SceneOf(sphere);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 200; ++i) {
    const double t = 0.37 * i;
    points.emplace_back(std::sin(t) * (0.1 + 0.004 * i), std::cos(1.3 * t) * 0.6, 0.3 + std::sin(0.7 * t));
  }
  const std::vector<float> d = DistancesToSurface(*scene, points, std::numeric_limits<float>::infinity());
  ASSERT_EQ(d.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(d[i], test::DistanceToMesh(points[i].cast<double>(), sphere), 1e-5) << i;
  }
}

TEST(DistancesToSurface, InfiniteBeyondTheLimit) {
  const auto scene = SceneOf(test::MakeGrid(1.0, 4));
  const std::vector<Eigen::Vector3f> points = {{0.2f, 0.1f, 0.25f}, {0.2f, 0.1f, 0.75f}, {3, 0, 0}};
  const std::vector<float> d = DistancesToSurface(*scene, points, 0.5f);
  EXPECT_NEAR(d[0], 0.25f, 1e-6);
  EXPECT_TRUE(std::isinf(d[1]));
  EXPECT_TRUE(std::isinf(d[2]));
}

}  // namespace
}  // namespace vscan::raycast
