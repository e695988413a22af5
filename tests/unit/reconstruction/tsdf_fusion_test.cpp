#include "reconstruction/tsdf_fusion.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "evaluation/ground_truth.h"
#include "mesh_checks.h"
#include "raycast/point_queries.h"
#include "scan_views.h"

namespace vscan::reconstruction {
namespace {

constexpr float kFusionVoxel = 0.002f;

TsdfFusionOptions Options() {
  TsdfFusionOptions options;
  options.tsdf.voxel_size = kFusionVoxel;
  options.tsdf.truncation_voxels = 4;
  return options;
}

float MaxDistance(const raycast::RaycastScene& truth, const TriangleMesh& mesh) {
  const std::vector<float> d =
      raycast::DistancesToSurface(truth, mesh.vertices, std::numeric_limits<float>::infinity());
  return d.empty() ? 0 : *std::max_element(d.begin(), d.end());
}

double FScore(const TriangleMesh& truth, const TriangleMesh& mesh, double tau) {
  evaluation::EvaluationOptions options;
  options.tau = tau;
  auto gt = evaluation::GroundTruth::Prepare(truth, options);
  EXPECT_TRUE(gt.ok());
  auto e = gt->EvaluateMesh(mesh);
  EXPECT_TRUE(e.ok()) << e.status().ToString();
  return e.ok() ? e->f_score : 0;
}

// A sphere of radius 0.1 m scanned from the six axis directions at about 1 mm per pixel.
TEST(TsdfFusion, SphereFromSixViews) {
  const Eigen::Vector3d centre(0.02, -0.01, 0.03);
  const TriangleMesh sphere = vscan::test::MakeIcosphere(centre, 0.1, 5);
  const auto scene = test::SceneOf(sphere);
  const sensor::PinholeCamera camera = sensor::CameraFromFov(240, 240, 60.0, 0.05, 2.0);
  const std::vector<RangeImage> images = test::SixViews(*scene, camera, centre, 0.3);
  TsdfFusionStats stats;
  auto mesh = FuseRangeImages(images, Options(), &stats);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_GT(mesh->triangles.size(), 10'000u);
  EXPECT_GT(stats.blocks, 0u);
  EXPECT_LT(MaxDistance(*scene, *mesh), 0.5f * kFusionVoxel);
  EXPECT_GT(FScore(sphere, *mesh, kFusionVoxel), 0.95);
  EXPECT_TRUE(test::ClosedAndConsistent(*mesh));
  EXPECT_EQ(test::ShareFacingAway(*mesh, centre.cast<float>()), 1.0);
}

// One view of a tilted square: an open sheet on the plane, facing the sensor.
class PlaneFromOneView : public ::testing::Test {
 protected:
  Eigen::Vector3d normal_ = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  TriangleMesh square_ = vscan::test::MakeSquare(Eigen::Vector3d::Zero(), normal_, 0.08);
  std::shared_ptr<const raycast::RaycastScene> scene_ = test::SceneOf(square_);
  std::vector<RangeImage> images_ = {test::ScanView(*scene_, sensor::CameraFromFov(200, 200, 50.0, 0.05, 2.0),
                                                    Eigen::Vector3d(0.05, 0.04, 0.35), Eigen::Vector3d::Zero())};
};

TEST_F(PlaneFromOneView, WithoutCarvingTheSheetLiesOnThePlane) {
  TsdfFusionOptions options = Options();
  options.tsdf.carve_empty_pixels = false;
  auto mesh = FuseRangeImages(images_, options);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ASSERT_GT(mesh->triangles.size(), 1000u);
  EXPECT_LT(MaxDistance(*scene_, *mesh), 0.5f * kFusionVoxel);
  EXPECT_GT(FScore(square_, *mesh, kFusionVoxel), 0.95);
  for (const auto& t : mesh->triangles) {
    const Eigen::Vector3f a = mesh->vertices[t[0]], b = mesh->vertices[t[1]], c = mesh->vertices[t[2]];
    const Eigen::Vector3f n = (b - a).cross(c - a);
    if (n.norm() > 1e-12f) {
      EXPECT_GT(n.normalized().dot(normal_.cast<float>()), 0.5f);
    }
  }
}

// Free space seen past the sheet's edge meets the band behind it: a lip of at most a couple of
// voxels along the edge, and no more.
TEST_F(PlaneFromOneView, CarvingLeavesAtMostALipAtTheEdge) {
  auto mesh = FuseRangeImages(images_, Options());
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_LT(MaxDistance(*scene_, *mesh), 2 * kFusionVoxel);
  EXPECT_GT(FScore(square_, *mesh, kFusionVoxel), 0.95);
}

TEST(TsdfFusion, SmallPiecesAreRemovedOnRequest) {
  const Eigen::Vector3d centre(0, 0, 0);
  TriangleMesh scene_mesh = vscan::test::MakeIcosphere(centre, 0.1, 4);
  // A small second sphere beside the first.
  const TriangleMesh speck = vscan::test::MakeIcosphere(Eigen::Vector3d(0.16, 0, 0), 0.008, 2);
  const auto offset = static_cast<uint32_t>(scene_mesh.vertices.size());
  scene_mesh.vertices.insert(scene_mesh.vertices.end(), speck.vertices.begin(), speck.vertices.end());
  for (auto t : speck.triangles) scene_mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const auto scene = test::SceneOf(scene_mesh);
  const sensor::PinholeCamera camera = sensor::CameraFromFov(160, 160, 70.0, 0.05, 2.0);
  const std::vector<RangeImage> images = test::SixViews(*scene, camera, centre, 0.3);
  TsdfFusionOptions options = Options();
  auto all = FuseRangeImages(images, options);
  options.min_component_triangles = 2000;
  auto cleaned = FuseRangeImages(images, options);
  ASSERT_TRUE(all.ok() && cleaned.ok());
  EXPECT_LT(cleaned->triangles.size(), all->triangles.size());
  for (const auto& v : cleaned->vertices) EXPECT_LT(v.x(), 0.14f);
}

// The blocks a fine voxel needs are counted before any is allocated: past max_block_bytes the
// fusion is refused, naming the voxel; the same view fits a bound just above what it took.
TEST_F(PlaneFromOneView, BlocksPastTheBoundAreRefusedBeforeAllocation) {
  TsdfFusionStats stats;
  ASSERT_TRUE(FuseRangeImages(images_, Options(), &stats).ok());
  ASSERT_GT(stats.blocks, 10u);
  const uint64_t block_bytes = sizeof(TsdfVoxel) * VoxelBlocks::kVoxels;
  TsdfFusionOptions bounded = Options();
  bounded.tsdf.max_block_bytes = stats.blocks * block_bytes / 2;
  const auto refused = FuseRangeImages(images_, bounded);
  ASSERT_EQ(refused.status().code(), StatusCode::kResourceExhausted) << refused.status().ToString();
  EXPECT_EQ(refused.status().field(), "tsdf.voxel_size");
  bounded.tsdf.max_block_bytes = stats.blocks * (block_bytes + 64);
  EXPECT_TRUE(FuseRangeImages(images_, bounded).ok());
}

// A stop reaches every stage: set before the fusion, or while a fine grid integrates.
TEST(TsdfFusion, ACancelEndsTheFusion) {
  const Eigen::Vector3d centre(0, 0, 0);
  const auto scene = test::SceneOf(vscan::test::MakeIcosphere(centre, 0.1, 5));
  const std::vector<RangeImage> images =
      test::SixViews(*scene, sensor::CameraFromFov(400, 400, 60.0, 0.05, 2.0), centre, 0.3);
  TsdfFusionOptions options = Options();
  options.tsdf.voxel_size = 0.0005f;
  std::atomic<bool> cancel{true};
  EXPECT_EQ(FuseRangeImages(images, options, nullptr, &cancel).status().code(), StatusCode::kCancelled);
  cancel = false;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    cancel = true;
  });
  const auto start = std::chrono::steady_clock::now();
  const auto stopped = FuseRangeImages(images, options, nullptr, &cancel);
  const auto took = std::chrono::steady_clock::now() - start;
  stopper.join();
  EXPECT_EQ(stopped.status().code(), StatusCode::kCancelled) << "fused in " << took.count() * 1e-9 << " s";
}

TEST(TsdfFusion, RejectsBadOptions) {
  TsdfFusionOptions options;
  options.tsdf.voxel_size = 0;
  auto bad = FuseRangeImages({}, options);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("tsdf.voxel_size"), std::string::npos);
  options = TsdfFusionOptions{};
  options.tsdf.truncation_voxels = 9;
  EXPECT_FALSE(FuseRangeImages({}, options).ok());
  auto empty = FuseRangeImages({}, TsdfFusionOptions{});
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
}

}  // namespace
}  // namespace vscan::reconstruction
