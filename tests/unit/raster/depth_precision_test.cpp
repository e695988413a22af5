// The paper's observation: the depth buffer loses precision as far/near grows. A plane centred at
// 2 m, far fixed at 4 m, near = far / ratio; the planes are set explicitly (no hugging).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "raster/raster_scanner.h"
#include "raster_test_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::raster {
namespace {

constexpr double kFar = 4.0;
constexpr double kDistance = 2.0;
const std::vector<double> kRatios = {10, 100, 1000, 10000};

struct Errors {
  double max = 0, rms = 0;
};

struct Row {
  const char* name;
  RasterMethod method;
  DepthFormat format;
  std::vector<Errors> errors;  // one per ratio
};

// Depth errors against the analytic plane over every pixel of one scan.
Errors Measure(RasterRenderer& renderer, RasterMethod method, DepthFormat format, double ratio) {
  sensor::PinholeCamera camera = sensor::CameraFromFov(640, 480, 40.0, kFar / ratio, kFar);
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(20 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()));
  raycast::SceneInstance plane;
  plane.mesh = vscan::test::Share(vscan::test::MakeGrid(1.2, 20));
  plane.world_from_object = Eigen::Translation3d(0, 0, kDistance) * tilt;
  const std::vector<raycast::SceneInstance> instances = {plane};
  const Eigen::Vector3d normal = tilt * Eigen::Vector3d::UnitZ();
  const double offset = normal.z() * kDistance;

  RasterOptions options;
  options.fields = kFieldPosition | kFieldPixel;
  options.frame = raycast::ScanFrame::kSensor;
  options.hug_scene_bounds = false;
  options.depth_format = format;
  auto cloud = RasterScan(renderer, "precision-plane", instances, camera, Pose3::Identity(), method, options);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  EXPECT_EQ(cloud->size(), camera.pixel_count());
  Errors e;
  for (size_t i = 0; i < cloud->size(); ++i) {
    const uint32_t u = cloud->pixels[i] % camera.width, v = cloud->pixels[i] / camera.width;
    const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx, (v + 0.5 - camera.cy) / camera.fy, 1.0);
    const double error = std::abs(cloud->positions[i].z() - offset / normal.dot(ray));
    e.max = std::max(e.max, error);
    e.rms += error * error;
  }
  e.rms = std::sqrt(e.rms / static_cast<double>(std::max<size_t>(cloud->size(), 1)));
  return e;
}

TEST(DepthPrecision, DepthBufferErrorGrowsWithFarOverNear) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  std::vector<Row> rows = {{"depth buffer, 24-bit", RasterMethod::kDepthBuffer, DepthFormat::kFixed24, {}},
                           {"depth buffer, 32F", RasterMethod::kDepthBuffer, DepthFormat::kFloat32, {}},
                           {"depth buffer, 32F reversed", RasterMethod::kDepthBuffer, DepthFormat::kFloat32Reversed, {}},
                           {"colour buffer (16-bit range)", RasterMethod::kColourBuffer, DepthFormat::kFloat32Reversed, {}}};
  for (Row& row : rows) {
    for (double ratio : kRatios) row.errors.push_back(Measure(*renderer, row.method, row.format, ratio));
  }

  std::printf("\nDepth error on a plane at %.0f m (640x480, far %.0f m, near = far / ratio), max / RMS in mm:\n\n",
              kDistance, kFar);
  std::printf("| method | far/near = 10 | 100 | 1000 | 10000 |\n|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    std::printf("| %s |", row.name);
    for (const Errors& e : row.errors) std::printf(" %.4g / %.4g |", e.max * 1e3, e.rms * 1e3);
    std::printf("\n");
  }
  std::printf("| 24-bit step at %.0f m |", kDistance);
  for (double ratio : kRatios) {
    const double n = kFar / ratio;
    std::printf(" %.4g |", kDistance * kDistance * (kFar - n) / (n * kFar) / 16777215.0 * 1e3);
  }
  std::printf("\n\n");

  const std::vector<Errors>& fixed24 = rows[0].errors;
  for (size_t i = 1; i < kRatios.size(); ++i) {
    EXPECT_GT(fixed24[i].max, fixed24[i - 1].max) << "far/near " << kRatios[i];
    EXPECT_GT(fixed24[i].rms, fixed24[i - 1].rms) << "far/near " << kRatios[i];
  }
  // The step grows about as 1 / near: a thousandfold from far/near 10 to 10000.
  EXPECT_GT(fixed24.back().rms, 100 * fixed24.front().rms);
  // A reversed float buffer keeps near-constant relative precision.
  EXPECT_LT(rows[2].errors.back().rms, fixed24.back().rms / 100);
}

}  // namespace
}  // namespace vscan::raster
