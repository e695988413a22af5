// A raster scan with returned light, its direct term from the shaders, gives the ray-cast backend's
// dark / saturated / measured verdicts on the same scene: a dark far plane, a mid-grey plane and a
// polished metal whose highlight saturates and whose rest is dark.
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "capture/measure_scan.h"
#include "raster/direct_light.h"
#include "raster/raster_scanner.h"
#include "raster_test_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::raster {
namespace {

// Pixels may differ only where the two backends' hits differ (a pixel centre within rounding of a
// silhouette, 0.2% in backend_agreement_test) or where the mean electrons lie within float
// rounding of a verdict's threshold (the full well, or min_snr x noise).
constexpr double kMaxVerdictMismatch = 0.005;

struct VerdictScene {
  sensor::PinholeCamera camera = sensor::CameraFromFov(400, 300, 50.0, 0.05, 10.0);
  Pose3 world_from_sensor = *PoseFromLookAt({0.2, 0.4, 1.0}, {0, 0, 0}, Eigen::Vector3d::UnitZ(), "test");
  std::vector<raycast::SceneInstance> instances;
  capture::MeasurementSpec spec;
};

void AddPlane(VerdictScene& s, const Eigen::Vector3d& centre, double half_side, double tilt_deg, uint32_t id) {
  raycast::SceneInstance plane;
  plane.mesh = vscan::test::Share(vscan::test::MakeGrid(half_side, 6));
  plane.world_from_object = s.world_from_sensor * Eigen::Translation3d(centre) *
                            Eigen::AngleAxisd(tilt_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitY());
  plane.instance_id = id;
  s.instances.push_back(plane);
}

VerdictScene MakeVerdictScene() {
  VerdictScene s;
  AddPlane(s, {-0.45, 0, 1.2}, 0.35, 25, 1);  // mid grey
  AddPlane(s, {0.1, 0, 1.0}, 0.25, -4, 2);    // polished metal, nearly facing the camera
  AddPlane(s, {0.2, 0, 2.8}, 1.5, 10, 3);     // dark and far, behind the others
  capture::ReturnedLightSpec light;
  light.emitter.radiant_intensity_w_per_sr = 1.0;
  light.pixel.gain_e = 2e4;
  light.materials = {sensor::Material{}, {0.5, 0.0, 0.7, 0.04}, {0.9, 1.0, 0.12, 0.04}, {0.01, 0.0, 0.9, 0.04}};
  s.spec.returned_light = light;
  s.spec.include_rejected = true;
  s.spec.fields = kFieldPosition | kFieldPixel | kFieldStatus;
  s.spec.seed = 11;
  return s;
}

// Status per pixel, kUnspecified where the cloud has no point.
std::vector<uint8_t> StatusImage(const PointCloud& cloud, const sensor::PinholeCamera& camera) {
  std::vector<uint8_t> image(camera.pixel_count(), static_cast<uint8_t>(PointStatus::kUnspecified));
  for (size_t i = 0; i < cloud.size(); ++i) image[cloud.pixels[i]] = cloud.statuses[i];
  return image;
}

class RasterLitVerdictsTest : public ::testing::TestWithParam<RasterMethod> {};

TEST_P(RasterLitVerdictsTest, MatchTheRayCastBackend) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const VerdictScene s = MakeVerdictScene();
  auto scene = raycast::RaycastScene::Build(s.instances);
  ASSERT_TRUE(scene.ok()) << scene.status().ToString();

  auto ray = capture::ScanMeasured(**scene, s.camera, s.world_from_sensor, s.spec, raycast::ScanFrame::kSensor,
                                   nullptr, nullptr, nullptr);
  ASSERT_TRUE(ray.ok()) << ray.status().ToString();

  const capture::ReturnedLightSpec& light = *s.spec.returned_light;
  const DirectLight direct{light.emitter, light.materials, light.default_material};
  RasterOptions options;
  options.fields = capture::CleanFieldsFor(s.spec);
  options.frame = raycast::ScanFrame::kSensor;
  auto lit = RasterScanLit(*renderer, "verdicts", s.instances, s.camera, s.world_from_sensor, GetParam(), direct,
                           options);
  ASSERT_TRUE(lit.ok()) << lit.status().ToString();
  auto raster = capture::MeasureScan(**scene, s.camera, s.world_from_sensor, std::move(lit->cloud), s.spec, nullptr,
                                     nullptr, lit->direct_radiance);
  ASSERT_TRUE(raster.ok()) << raster.status().ToString();

  const std::vector<uint8_t> a = StatusImage(*ray, s.camera), b = StatusImage(*raster, s.camera);
  size_t both = 0, mismatch = 0, dark = 0, saturated = 0, measured = 0;
  for (size_t p = 0; p < a.size(); ++p) {
    const auto none = static_cast<uint8_t>(PointStatus::kUnspecified);
    if (a[p] == none && b[p] == none) continue;
    ++both;
    mismatch += a[p] != b[p];
    dark += a[p] == static_cast<uint8_t>(PointStatus::kRejectedDark);
    saturated += a[p] == static_cast<uint8_t>(PointStatus::kRejectedSaturated);
    measured += a[p] == static_cast<uint8_t>(PointStatus::kMeasured);
  }
  std::printf("%zu pixels: %zu measured, %zu dark, %zu saturated (ray cast); %zu differ (%.3f%%)\n", both, measured,
              dark, saturated, mismatch, 100.0 * mismatch / both);
  EXPECT_GT(measured, 5000u);
  EXPECT_GT(dark, 5000u);
  EXPECT_GT(saturated, 50u);
  EXPECT_LE(mismatch, kMaxVerdictMismatch * both);
}

INSTANTIATE_TEST_SUITE_P(Methods, RasterLitVerdictsTest,
                         ::testing::Values(RasterMethod::kDepthBuffer, RasterMethod::kColourBuffer),
                         [](const auto& info) {
                           return info.param == RasterMethod::kDepthBuffer ? "Depth" : "Colour";
                         });

}  // namespace
}  // namespace vscan::raster
