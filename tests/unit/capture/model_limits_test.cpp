// The measurement model at its limits: continuous steep surfaces, degenerate and huge inputs, empty
// and fully rejected scans, shadows at small and large scales.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "capture/measure_scan.h"
#include "capture_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::capture {
namespace {

using test::Build;
using test::Code;
using test::kDeg;
using test::TruthSpec;
using test::Camera;
using test::Measure;


raycast::SceneInstance Mesh(TriangleMesh mesh, uint32_t id) {
  raycast::SceneInstance instance;
  instance.mesh = vscan::test::Share(std::move(mesh));
  instance.instance_id = id;
  return instance;
}


TEST(FlyingPixelTest, NoneOnAContinuousSteepPlane) {
  // A plane tilted 70 degrees away from the camera: at 64 pixels over 60 degrees neighbouring depths
  // differ by about 9 cm, far above the 2 cm edge threshold, yet there is no edge to mix across.
  const Eigen::Vector3d normal(0, std::sin(70 * kDeg), -std::cos(70 * kDeg));
  const auto scene = Build({Mesh(vscan::test::MakeSquare({0, 0, 2}, normal, 50), 1)});
  MeasurementSpec spec = TruthSpec();
  spec.flying_pixels.enabled = true;
  spec.seed = 4;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, Camera(64, 48, 60), spec, &stats);
  ASSERT_GT(cloud.size(), 2000u);
  std::vector<float> depth(64 * 48, NAN);
  for (size_t i = 0; i < cloud.size(); ++i) depth[cloud.pixels[i]] = cloud.clean_positions[i].z();
  float largest_jump = 0;
  for (size_t p = 0; p + 64 < depth.size(); ++p) {
    if (std::isfinite(depth[p]) && std::isfinite(depth[p + 64])) {
      largest_jump = std::max(largest_jump, std::abs(depth[p + 64] - depth[p]));
    }
  }
  EXPECT_GT(largest_jump, 0.05f) << "the test needs depth jumps above the edge threshold";
  EXPECT_EQ(stats.flying_pixels, 0u);
}

TEST(FlyingPixelTest, StillAtTheSilhouetteOfACurvedObject) {
  const auto scene = Build({test::Sphere({0, 0, 2}, 0.5), test::Plane(3.0, 5.0)});
  MeasurementSpec spec = TruthSpec();
  spec.flying_pixels.enabled = true;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, Camera(200, 200, 40), spec, &stats);
  // Every sphere pixel beside a plane pixel is at an edge (the plane is 1 m or more behind).
  std::vector<uint32_t> instance(200 * 200, 0);
  for (size_t i = 0; i < cloud.size(); ++i) instance[cloud.pixels[i]] = cloud.instance_ids[i];
  size_t rim = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t p = cloud.pixels[i], u = p % 200, v = p / 200;
    if (instance[p] != test::kSphereId || u == 0 || v == 0 || u == 199 || v == 199) continue;
    const bool at_rim = instance[p - 1] == test::kPlaneId || instance[p + 1] == test::kPlaneId ||
                        instance[p - 200] == test::kPlaneId || instance[p + 200] == test::kPlaneId;
    rim += at_rim;
    if (at_rim) {
      EXPECT_EQ(cloud.statuses[i], Code(PointStatus::kFlyingPixel)) << "pixel " << u << "," << v;
    }
  }
  EXPECT_GT(rim, 100u);
}

TEST(FlyingPixelTest, NoneAgainstABackgroundOutOfRange) {
  MeasurementSpec spec = TruthSpec();
  spec.flying_pixels.enabled = true;
  const auto camera = Camera(100, 100, 40, /*far=*/3.0);
  MeasureStats in_range, beyond;
  const auto near_wall = Build({test::Plane(2.5, 5.0), test::Box({-0.2, -0.2, 1.0}, {0.2, 0.2, 1.4})});
  Measure(*near_wall, camera, spec, &in_range);
  EXPECT_GT(in_range.flying_pixels, 50u);
  // The wall beyond far is found (and rejected) by the widened clean scan, but no pixel mixes with it.
  const auto far_wall = Build({test::Plane(5.0, 10.0), test::Box({-0.2, -0.2, 1.0}, {0.2, 0.2, 1.4})});
  const PointCloud cloud = Measure(*far_wall, camera, spec, &beyond);
  EXPECT_GT(beyond.rejected_out_of_range, 1000u);
  EXPECT_EQ(beyond.flying_pixels, 0u);
  for (const Eigen::Vector3f& p : cloud.positions) EXPECT_LE(p.z(), 3.0f);
}

TEST(MeasureScanLimits, HugeNoiseOrDistortionNeverReturnsNonFinitePoints) {
  const auto scene = Build({test::Plane(2.0, 5.0)});
  for (int which = 0; which < 2; ++which) {
    MeasurementSpec spec = TruthSpec();
    if (which == 0) spec.noise.sigma_a = 1e39;  // finite as a double, beyond float
    if (which == 1) spec.distortion.k1 = 1e38;
    spec.fields |= kFieldEstimatedNormal;
    MeasureStats stats;
    const PointCloud cloud = Measure(*scene, Camera(40, 30, 60), spec, &stats);
    for (size_t i = 0; i < cloud.size(); ++i) {
      ASSERT_TRUE(cloud.positions[i].allFinite()) << "case " << which << " point " << i;
      ASSERT_TRUE(std::isfinite(cloud.ranges[i]));
    }
    EXPECT_TRUE(std::isfinite(stats.max_range));
    EXPECT_EQ(stats.points + stats.rejected() + stats.dropped, stats.hits);
  }
}

TEST(MeasureScanLimits, EmptyAndFullyRejectedScansWithEstimatedNormals) {
  MeasurementSpec spec = TruthSpec();
  spec.fields |= kFieldEstimatedNormal;
  spec.include_rejected = true;
  spec.noise.sigma_a = 0.001;
  // Nothing in view.
  const auto empty = Build({});
  MeasureStats stats;
  EXPECT_EQ(Measure(*empty, Camera(32, 24, 60), spec, &stats).size(), 0u);
  EXPECT_EQ(stats.hits, 0u);
  // Everything beyond far: returned as rejected, with zero estimated normals.
  const auto far = Build({test::Plane(5.0, 20.0)});
  const PointCloud cloud = Measure(*far, Camera(32, 24, 60, /*far=*/2.0), spec, &stats);
  ASSERT_EQ(cloud.size(), 32u * 24u);
  EXPECT_EQ(stats.points, 0u);
  EXPECT_EQ(stats.min_range, 0.0);
  EXPECT_EQ(stats.max_range, 0.0);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.statuses[i], Code(PointStatus::kRejectedOutOfRange));
    EXPECT_EQ(cloud.estimated_normals[i], Eigen::Vector3f::Zero());
  }
}

// A structured-light scanner at the world position `origin`, looking along +z at a plane at depth 0.5
// with a strip `gap` metres in front of it, and a large wall beyond the far limit.
MeasureStats ShadowedStrip(const Eigen::Vector3d& origin, double gap, double wall_depth) {
  Pose3 world_from_sensor = Pose3::Identity();
  world_from_sensor.translation() = origin;
  const auto place = [&](TriangleMesh mesh) {
    for (Eigen::Vector3f& v : mesh.vertices) v = (world_from_sensor * v.cast<double>()).cast<float>();
    return mesh;
  };
  TriangleMesh strip;
  for (const auto& [x, y] : {std::pair{0.0, -0.05}, {0.01, -0.05}, {0.01, 0.05}, {0.0, 0.05}}) {
    strip.vertices.emplace_back(x, y, 0.5 - gap);
  }
  strip.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto scene = Build({Mesh(place(vscan::test::MakeSquare({0, 0, 0.5}, {0, 0, -1}, 0.06)), 1),
                            Mesh(place(std::move(strip)), 2),
                            Mesh(place(vscan::test::MakeSquare({0, 0, wall_depth}, {0, 0, -1}, wall_depth)), 3)});
  MeasurementSpec spec = TruthSpec();
  sensor::StructuredLight sl;
  sl.camera = sensor::CameraFromFov(400, 400, 14, 0.3, 10.0);
  sl.projector_offset = {0.2, 0, 0};
  sl.projector_hfov_deg = sl.projector_vfov_deg = 120;
  spec.structured_light = sl;
  MeasureStats stats;
  auto cloud = ScanMeasured(*scene, sl.camera, world_from_sensor, spec, raycast::ScanFrame::kSensor, nullptr, nullptr,
                            &stats);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  return stats;
}

TEST(MeasuredShadowLimits, AStripAMillimetreAboveASurfaceCastsItsShadow) {
  // Shadow width 2 mm x 0.2 / 0.5 = 0.8 mm, about 3 columns of 0.25 mm over the strip's 10 cm.
  const MeasureStats near_wall = ShadowedStrip(Eigen::Vector3d::Zero(), 0.002, 5.0);
  EXPECT_GT(near_wall.rejected_shadowed, 600u);
  // A wall far away (beyond far, so never measured) must not change the shadow.
  const MeasureStats far_wall = ShadowedStrip(Eigen::Vector3d::Zero(), 0.002, 38.0);
  EXPECT_EQ(far_wall.rejected_shadowed, near_wall.rejected_shadowed);
}

TEST(MeasuredShadowLimits, NoSelfShadowFarFromTheWorldOrigin) {
  for (const double offset : {0.0, 100.0, 1000.0}) {
    const MeasureStats stats = ShadowedStrip(Eigen::Vector3d(offset, -offset, offset), 0.002, 5.0);
    EXPECT_LT(stats.rejected_shadowed, 1500u) << "offset " << offset;
    EXPECT_GT(stats.rejected_shadowed, 600u) << "offset " << offset;
  }
}

}  // namespace
}  // namespace vscan::capture
