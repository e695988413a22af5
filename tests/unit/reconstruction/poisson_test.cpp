#include "reconstruction/poisson_pipeline.h"

#include <gtest/gtest.h>

#include "evaluation/ground_truth.h"
#include "mesh_checks.h"
#include "reconstruction/distance_trim.h"
#include "reconstruction/oriented_normals.h"
#include "scan_views.h"

namespace vscan::reconstruction {
namespace {

TEST(VoxelDownsample, OnePointPerVoxelWithTheMeanViewDirection) {
  const std::vector<Eigen::Vector3f> a = {{0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}, {1.5f, 0.5f, 0.5f}};
  const std::vector<Eigen::Vector3f> b = {{0.5f, 0.5f, 0.5f}, {2.5f, 0.5f, 0.5f}};
  const std::vector<ScanPoints> scans = {{a, Eigen::Vector3f(0.2f, 0.2f, 10)}, {b, Eigen::Vector3f(0.5f, 10, 0.5f)}};
  const UnionCloud cloud = VoxelDownsample(scans, 1.0f);
  ASSERT_EQ(cloud.positions.size(), 3u);
  // Voxel (0,0,0) holds three points from both scans.
  EXPECT_TRUE(cloud.positions[0].isApprox(Eigen::Vector3f(0.3f, 0.3f, 0.3f)));
  EXPECT_NEAR(cloud.view_directions[0].norm(), 1.0f, 1e-6f);
  EXPECT_GT(cloud.view_directions[0].y(), 0.3f);
  EXPECT_GT(cloud.view_directions[0].z(), 0.3f);
  EXPECT_TRUE(cloud.positions[1].isApprox(Eigen::Vector3f(1.5f, 0.5f, 0.5f)));
  EXPECT_TRUE(cloud.view_directions[2].isApprox(Eigen::Vector3f(-2, 9.5f, 0).normalized()));
}

TEST(OrientNormals, NormalsFaceTheirSensors) {
  std::vector<Eigen::Vector3f> points, views;
  for (int i = 0; i < 20; ++i) {
    for (int j = 0; j < 20; ++j) {
      points.emplace_back(0.01f * i, 0.01f * j, 0);
      views.push_back(i < 10 ? Eigen::Vector3f(0.1f, 0, 1).normalized() : Eigen::Vector3f(0, 0.2f, 1).normalized());
    }
  }
  auto oriented = OrientNormals(points, views, 8);
  ASSERT_TRUE(oriented.ok()) << oriented.status().ToString();
  ASSERT_EQ(oriented->normals.size(), points.size());
  for (const auto& n : oriented->normals) EXPECT_NEAR(n.z(), 1.0f, 1e-4f);
  views.pop_back();
  EXPECT_FALSE(OrientNormals(points, views, 8).ok());
}

TEST(TrimFarFromPoints, KeepsOnlyWhatWasSeen) {
  TriangleMesh mesh = vscan::test::MakeGrid(1.0, 20);  // the square [-1, 1]^2
  std::vector<Eigen::Vector3f> seen;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      if (i <= 20) seen.emplace_back(-1 + 0.05f * i, -1 + 0.05f * j, 0);
    }
  }
  const size_t before = mesh.triangles.size();
  const size_t dropped = TrimFarFromPoints(mesh, seen, 0.06f);
  EXPECT_EQ(dropped + mesh.triangles.size(), before);
  EXPECT_NEAR(static_cast<double>(mesh.triangles.size()) / before, 0.5, 0.06);
  for (const auto& v : mesh.vertices) EXPECT_LE(v.x(), 0.06f);
}

// A sphere of radius 0.1 m from six views: the closed Poisson surface lies on it and faces out.
TEST(PoissonPipeline, SphereFromSixViews) {
  const Eigen::Vector3d centre(0.01, 0.02, -0.01);
  const TriangleMesh sphere = vscan::test::MakeIcosphere(centre, 0.1, 5);
  const auto scene = test::SceneOf(sphere);
  const sensor::PinholeCamera camera = sensor::CameraFromFov(100, 100, 60.0, 0.05, 2.0);
  std::vector<PointCloud> clouds;
  std::vector<ScanPoints> scans;
  for (int a = 0; a < 3; ++a) {
    for (double sign : {1.0, -1.0}) {
      const Eigen::Vector3d eye = centre + sign * 0.3 * Eigen::Vector3d::Unit(a);
      const Eigen::Vector3d up = a == 2 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
      auto pose = PoseFromLookAt(eye, centre, up, "test");
      ASSERT_TRUE(pose.ok());
      auto cloud = raycast::Scan(*scene, camera, *pose, raycast::ScanOptions{kFieldPosition});
      ASSERT_TRUE(cloud.ok());
      clouds.push_back(std::move(cloud).value());
      scans.push_back({clouds.back().positions, eye.cast<float>()});
    }
  }
  // clouds may have moved while growing: point the spans at their final storage.
  for (size_t i = 0; i < scans.size(); ++i) scans[i].points = clouds[i].positions;
  PoissonPipelineOptions options;
  options.voxel_size = 0.003f;
  options.poisson.depth = 6;
  PoissonPipelineStats stats;
  auto mesh = ReconstructPoisson(scans, options, &stats);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_GT(stats.union_points, 5'000u);
  ASSERT_GT(mesh->triangles.size(), 1000u);
  EXPECT_GT(test::ShareFacingAway(*mesh, centre.cast<float>()), 0.99);
  evaluation::EvaluationOptions eval;
  eval.tau = 0.003;
  auto truth = evaluation::GroundTruth::Prepare(sphere, eval);
  ASSERT_TRUE(truth.ok());
  auto e = truth->EvaluateMesh(*mesh);
  ASSERT_TRUE(e.ok());
  EXPECT_GT(e->f_score, 0.9);
}

TEST(PoissonPipeline, RejectsBadOptions) {
  PoissonPipelineOptions options;
  options.voxel_size = -1;
  auto bad = ReconstructPoisson({}, options);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("poisson.voxel_size"), std::string::npos);
  options = PoissonPipelineOptions{};
  options.poisson.depth = 0;
  EXPECT_FALSE(PoissonPcl({}, {}, options.poisson).ok());
}

}  // namespace
}  // namespace vscan::reconstruction
