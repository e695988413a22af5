// A tilted plane at a known distance: every pixel's depth (depth-buffer method) or range
// (colour-buffer method) within the method's quantisation of the truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "raster/raster_scanner.h"
#include "raster/view_planes.h"
#include "raster_test_scenes.h"
#include "vscan_test/meshes.h"

namespace vscan::raster {
namespace {

constexpr uint32_t kInstanceId = 7;

struct PlaneScene {
  sensor::PinholeCamera camera;
  Pose3 world_from_sensor;
  std::vector<raycast::SceneInstance> instances;
  Eigen::Vector3d sensor_normal;  // unit, facing the sensor
  double sensor_offset = 0;       // plane: sensor_normal . p = sensor_offset

  // Depth of the plane along the ray through pixel (u, v)'s centre.
  double TrueDepth(uint32_t u, uint32_t v) const {
    const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx, (v + 0.5 - camera.cy) / camera.fy, 1.0);
    return sensor_offset / sensor_normal.dot(ray);
  }
};

// A plane of small triangles through (0, 0, 2 m) in front of a sensor at an arbitrary pose, tilted
// about both image axes so that depth varies along rows and columns.
PlaneScene MakePlaneScene() {
  PlaneScene s;
  s.camera = sensor::CameraFromFov(640, 480, 40.0, 0.05, 10.0);
  s.camera.cx += 3.3;  // off-centre principal point
  s.camera.cy -= 7.6;
  s.camera.lighting = {1.0, 0.5, 0.2, 0.1};
  s.world_from_sensor = *PoseFromLookAt({0.3, -0.2, 1.5}, {1.0, 2.0, 0.4}, Eigen::Vector3d::UnitZ(), "test");
  const Eigen::Quaterniond tilt = Eigen::AngleAxisd(30 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(20 * std::numbers::pi / 180, Eigen::Vector3d::UnitY());
  const Eigen::Vector3d centre(0, 0, 2);
  raycast::SceneInstance plane;
  plane.mesh = vscan::test::Share(vscan::test::MakeGrid(1.5, 20));
  plane.world_from_object = s.world_from_sensor * Eigen::Translation3d(centre) * tilt;
  plane.instance_id = kInstanceId;
  s.instances.push_back(plane);
  s.sensor_normal = -(tilt * Eigen::Vector3d::UnitZ());
  if (s.sensor_normal.z() > 0) s.sensor_normal = -s.sensor_normal;
  s.sensor_offset = s.sensor_normal.dot(centre);
  return s;
}

// One quantisation step of window depth d: the 24-bit step, or the float's ulp at d. With the
// standard mapping d is near 1, where the float ulp is the 24-bit step; the GPU's single-precision
// arithmetic on d has errors of that size too, so a float32 buffer gains nothing there.
double DepthStep(DepthFormat format, double d) {
  if (format != DepthFormat::kFloat32Reversed) return 1.0 / 16777215.0;
  const auto f = static_cast<float>(d);
  return std::nextafter(f, 2.0f) - f;
}

// Allowed error in steps: half a step of rounding into the buffer plus the GPU's float32
// evaluation of d (vertex transform, clipping, interpolation), a few ulps (measured 3.4 and 6.5 on
// llvmpipe). A pixel-centre or row-order mistake costs thousands of steps.
double AllowedSteps(DepthFormat format) { return format == DepthFormat::kFloat32Reversed ? 10.0 : 5.0; }

double WindowDepth(double z, double n, double f, bool reversed) {
  return reversed ? n * (f - z) / (z * (f - n)) : f * (z - n) / (z * (f - n));
}

struct PlaneCase {
  RasterMethod method;
  DepthFormat format;
  const char* name;
};

class PlaneTest : public ::testing::TestWithParam<PlaneCase> {};

TEST_P(PlaneTest, EveryPixelWithinQuantisationOfTheTruth) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const PlaneScene s = MakePlaneScene();
  RasterOptions options;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  options.depth_format = GetParam().format;
  RasterStats stats;
  auto cloud = RasterScan(*renderer, "plane", s.instances, s.camera, s.world_from_sensor, GetParam().method, options, &stats);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  ASSERT_EQ(cloud->size(), s.camera.pixel_count()) << "the plane fills the frame";

  const bool depth_method = GetParam().method == RasterMethod::kDepthBuffer;
  const bool reversed = GetParam().format == DepthFormat::kFloat32Reversed;
  const double range_step = (stats.far_range - stats.near_range) / 65535.0;
  const double max_intensity = s.camera.lighting.power / (s.camera.lighting.constant +
                                                          (s.camera.lighting.linear + s.camera.lighting.quadratic * stats.near_range) *
                                                              stats.near_range);
  double worst_steps = 0;
  for (size_t i = 0; i < cloud->size(); ++i) {
    ASSERT_EQ(cloud->pixels[i], i);
    const uint32_t u = static_cast<uint32_t>(i % s.camera.width), v = static_cast<uint32_t>(i / s.camera.width);
    const Eigen::Vector3d ray((u + 0.5 - s.camera.cx) / s.camera.fx, (v + 0.5 - s.camera.cy) / s.camera.fy, 1.0);
    const double z_true = s.TrueDepth(u, v);
    const Eigen::Vector3d p = cloud->positions[i].cast<double>();
    // The point lies on the ray through the pixel centre.
    ASSERT_NEAR(p.x(), p.z() * ray.x(), 1e-6 * p.norm()) << "pixel " << u << "," << v;
    ASSERT_NEAR(p.y(), p.z() * ray.y(), 1e-6 * p.norm()) << "pixel " << u << "," << v;

    const double float_slack = 2.0 * std::ldexp(p.norm(), -24);  // the output is single precision
    if (depth_method) {
      const double d = WindowDepth(z_true, stats.near, stats.far, reversed);
      const double step = DepthStep(GetParam().format, d) * DepthPerUnitD(z_true, stats.near, stats.far);
      const double error = std::abs(p.z() - z_true);
      worst_steps = std::max(worst_steps, error / step);
      ASSERT_LE(error, AllowedSteps(GetParam().format) * step + float_slack) << "pixel " << u << "," << v << " z " << z_true;
    } else {
      const double range_true = z_true * ray.norm();
      const double error = std::abs(cloud->ranges[i] - range_true);
      worst_steps = std::max(worst_steps, error / range_step);
      ASSERT_LE(error, range_step + float_slack) << "pixel " << u << "," << v << " range " << range_true;
    }
    ASSERT_GT(cloud->normals[i].cast<double>().dot(s.sensor_normal), 1 - 1e-6);
    ASSERT_EQ(cloud->instance_ids[i], kInstanceId);
    const double intensity = sensor::Intensity(s.camera.lighting, z_true * ray.norm(), -s.sensor_normal.dot(ray) / ray.norm());
    ASSERT_NEAR(cloud->intensities[i], intensity, depth_method ? 1e-5 : 0.5 / 255 * max_intensity + 1e-5);
  }
  std::printf("%s: planes [%.6f, %.6f] m, worst error %.3f quantisation steps\n", GetParam().name, stats.near,
              stats.far, worst_steps);
}

TEST_P(PlaneTest, WorldPointsLieOnThePlane) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  const PlaneScene s = MakePlaneScene();
  RasterOptions options;
  options.depth_format = GetParam().format;
  auto cloud = RasterScan(*renderer, "plane", s.instances, s.camera, s.world_from_sensor, GetParam().method, options);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  const Eigen::Vector3d world_normal = s.world_from_sensor.linear() * s.sensor_normal;
  const double offset = world_normal.dot(s.world_from_sensor * (s.sensor_offset * s.sensor_normal));
  double worst = 0;
  for (size_t i = 0; i < cloud->size(); ++i) {
    worst = std::max(worst, std::abs(world_normal.dot(cloud->positions[i].cast<double>()) - offset));
    ASSERT_GT(cloud->normals[i].cast<double>().dot(world_normal), 1 - 1e-6);
  }
  EXPECT_LT(worst, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    Methods, PlaneTest,
    ::testing::Values(PlaneCase{RasterMethod::kDepthBuffer, DepthFormat::kFixed24, "DepthFixed24"},
                      PlaneCase{RasterMethod::kDepthBuffer, DepthFormat::kFloat32, "DepthFloat32"},
                      PlaneCase{RasterMethod::kDepthBuffer, DepthFormat::kFloat32Reversed, "DepthFloat32Reversed"},
                      PlaneCase{RasterMethod::kColourBuffer, DepthFormat::kFloat32Reversed, "Colour"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace vscan::raster
