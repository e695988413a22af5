// The raster shaders' direct term of the returned light against the CPU's (sensor::DirectRadiance,
// the same BRDF in double precision at the decoded hit point and normal), pixel by pixel, on planes
// whose answer is known: a Lambertian plane (also against albedo / pi x I cos / r^2), a polished
// metal (a highlight only about the mirror direction), a rough plastic lit by an offset projector
// with a cone (0 outside it), and three objects of different materials in one frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "raster/direct_light.h"
#include "raster/raster_scanner.h"
#include "raster_test_scenes.h"
#include "sensor/brdf.h"
#include "vscan_test/meshes.h"

namespace vscan::raster {
namespace {

// The shader works in single precision at its fragment's interpolated position, the CPU in double
// at the point decoded on the pixel centre's ray: per pixel they agree within 1e-4 of the value
// (float rounding through the formulas), plus the radiance's change over 1/32 pixel, since the
// fragment's point is interpolated from vertices the rasteriser snaps to 1/256 pixel, in float.
// That second term matters only on a polished lobe's flanks (30% per pixel at roughness 0.08),
// where the two differ by up to 0.2%, as a shift of about 1/100 pixel would make.
constexpr double kRelativeTolerance = 1e-4;
constexpr double kSnapPixels = 1.0 / 32;
constexpr double kFloorRadiance = 1e-9;

sensor::Material Lambertian(double albedo) { return {albedo, 0.0, 1.0, 0.0}; }

struct LitScene {
  sensor::PinholeCamera camera = sensor::CameraFromFov(320, 240, 40.0, 0.05, 10.0);
  Pose3 world_from_sensor = *PoseFromLookAt({0.3, -0.2, 1.5}, {1.0, 2.0, 0.4}, Eigen::Vector3d::UnitZ(), "test");
  std::vector<raycast::SceneInstance> instances;
  std::vector<sensor::Material> materials;
  DirectLight light;

  // A grid square of this half side, centred at sensor-frame `centre`, its normal tilted from the
  // sensor's -z by `tilt` (about x then y); returns the sensor-frame unit normal towards the sensor.
  Eigen::Vector3d AddPlane(const Eigen::Vector3d& centre, double half_side, const Eigen::Quaterniond& tilt,
                           uint32_t id) {
    raycast::SceneInstance plane;
    plane.mesh = vscan::test::Share(vscan::test::MakeGrid(half_side, 8));
    plane.world_from_object = world_from_sensor * Eigen::Translation3d(centre) * tilt;
    plane.instance_id = id;
    instances.push_back(plane);
    Eigen::Vector3d n = tilt * Eigen::Vector3d::UnitZ();
    return n.z() > 0 ? Eigen::Vector3d(-n) : n;
  }
};

Eigen::Quaterniond Tilt(double about_x_deg, double about_y_deg) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(about_x_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(about_y_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitY()));
}

LitCloud ScanLit(LitScene& s, RasterMethod method, const std::string& key) {
  s.light.materials = s.materials;
  RasterOptions options;
  options.fields = kFieldPosition | kFieldNormal | kFieldInstanceId | kFieldPixel;
  options.frame = raycast::ScanFrame::kSensor;
  RasterRenderer* renderer = testing::SharedRenderer();
  if (renderer == nullptr) return {};
  auto lit = RasterScanLit(*renderer, key, s.instances, s.camera, s.world_from_sensor, method, s.light, options);
  EXPECT_TRUE(lit.ok()) << lit.status().ToString();
  return lit.ok() ? std::move(*lit) : LitCloud{};
}

// What capture::ReturnedSignals computes for point i on the CPU.
double CpuRadiance(const LitCloud& lit, const DirectLight& light, size_t i) {
  const Eigen::Vector3d p = lit.cloud.positions[i].cast<double>();
  Eigen::Vector3d n = lit.cloud.normals[i].cast<double>();
  if (n.dot(p) > 0) n = -n;
  return sensor::DirectRadiance(MaterialOf(light, lit.cloud.instance_ids[i]), p, n, light.emitter,
                                Eigen::Vector3d::Zero());
}

// Worst |shader - CPU| over its tolerance (pass: below 1), over the frame; skip(i) leaves point i out.
template <typename Skip>
double WorstError(const LitCloud& lit, const DirectLight& light, const sensor::PinholeCamera& camera, Skip skip) {
  std::vector<double> cpu(lit.cloud.size());
  for (size_t i = 0; i < cpu.size(); ++i) cpu[i] = CpuRadiance(lit, light, i);
  const std::vector<int64_t> at = testing::PointOfPixel(lit.cloud, camera);
  double worst = 0;
  for (size_t i = 0; i < cpu.size(); ++i) {
    if (skip(i)) continue;
    const int64_t u = lit.cloud.pixels[i] % camera.width, v = lit.cloud.pixels[i] / camera.width;
    double slope = 0;  // largest change to a 4-neighbour on the same object
    for (const auto& [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      if (u + du < 0 || v + dv < 0 || u + du >= camera.width || v + dv >= camera.height) continue;
      const int64_t k = at[static_cast<size_t>((v + dv) * camera.width + u + du)];
      if (k < 0 || lit.cloud.instance_ids[k] != lit.cloud.instance_ids[i]) continue;
      slope = std::max(slope, std::abs(cpu[k] - cpu[i]));
    }
    const double allowed = kRelativeTolerance * std::max(cpu[i], kFloorRadiance) + kSnapPixels * slope;
    worst = std::max(worst, std::abs(lit.direct_radiance[i] - cpu[i]) / allowed);
  }
  return worst;
}

double WorstError(const LitCloud& lit, const DirectLight& light, const sensor::PinholeCamera& camera) {
  return WorstError(lit, light, camera, [](size_t) { return false; });
}

class RasterDirectLightTest : public ::testing::TestWithParam<RasterMethod> {
 protected:
  std::string Key(const char* name) const {
    return std::string(name) + (GetParam() == RasterMethod::kDepthBuffer ? "/depth" : "/colour");
  }
};

TEST_P(RasterDirectLightTest, LambertianPlaneIsAlbedoOverPiTimesIntensityCosOverRSquared) {
  LitScene s;
  const Eigen::Vector3d centre(0.05, -0.03, 1.2);
  const Eigen::Vector3d n = s.AddPlane(centre, 1.0, Tilt(25, -15), 1);
  s.materials = {Lambertian(0.5), Lambertian(0.7)};
  s.light.emitter.radiant_intensity_w_per_sr = 3.0;  // at the camera, lighting every direction
  const LitCloud lit = ScanLit(s, GetParam(), Key("lambert"));
  ASSERT_GT(lit.cloud.size(), s.camera.pixel_count() * 9 / 10);
  ASSERT_EQ(lit.direct_radiance.size(), lit.cloud.size());
  double worst_closed_form = 0;
  for (size_t i = 0; i < lit.cloud.size(); ++i) {
    const uint32_t pixel = lit.cloud.pixels[i];
    const uint32_t u = pixel % s.camera.width, v = pixel / s.camera.width;
    const Eigen::Vector3d ray((u + 0.5 - s.camera.cx) / s.camera.fx, (v + 0.5 - s.camera.cy) / s.camera.fy, 1.0);
    const Eigen::Vector3d p = ray * (n.dot(centre) / n.dot(ray));  // the true hit of the pixel's centre ray
    const double r = p.norm();
    const double expected = 0.7 / std::numbers::pi * 3.0 * std::abs(n.dot(p)) / r / (r * r);
    worst_closed_form = std::max(worst_closed_form, std::abs(lit.direct_radiance[i] - expected) / expected);
  }
  const double worst = WorstError(lit, s.light, s.camera);
  std::printf("lambertian: worst relative error %.2e vs the closed form, %.2f of the tolerance vs the CPU\n",
              worst_closed_form, worst);
  EXPECT_LT(worst_closed_form, kRelativeTolerance);
  EXPECT_LT(worst, 1.0);
}

TEST_P(RasterDirectLightTest, PolishedMetalShinesOnlyAboutTheMirrorDirection) {
  LitScene s;
  const Eigen::Vector3d centre(0, 0, 1.0);
  const Eigen::Vector3d n = s.AddPlane(centre, 1.0, Tilt(6, 4), 2);
  s.materials = {Lambertian(0.5), Lambertian(0.5), {0.9, 1.0, 0.08, 0.04}};
  const LitCloud lit = ScanLit(s, GetParam(), Key("metal"));
  ASSERT_GT(lit.cloud.size(), s.camera.pixel_count() * 9 / 10);
  // With the emitter at the camera the mirror pixel sees the plane along its normal.
  const Eigen::Vector3d foot = n * n.dot(centre);
  const double mirror_u = s.camera.fx * foot.x() / foot.z() + s.camera.cx;
  const double mirror_v = s.camera.fy * foot.y() / foot.z() + s.camera.cy;
  size_t brightest = 0;
  for (size_t i = 0; i < lit.cloud.size(); ++i) {
    if (lit.direct_radiance[i] > lit.direct_radiance[brightest]) brightest = i;
  }
  const double peak = lit.direct_radiance[brightest];
  const uint32_t bu = lit.cloud.pixels[brightest] % s.camera.width, bv = lit.cloud.pixels[brightest] / s.camera.width;
  EXPECT_LT(std::hypot(bu + 0.5 - mirror_u, bv + 0.5 - mirror_v), 1.5);
  // Far from the mirror direction (15 degrees off the normal) the lobe has died away.
  size_t far_pixels = 0;
  for (size_t i = 0; i < lit.cloud.size(); ++i) {
    const Eigen::Vector3d p = lit.cloud.positions[i].cast<double>();
    if (std::abs(n.dot(p.normalized())) > std::cos(15 * std::numbers::pi / 180)) continue;
    ++far_pixels;
    EXPECT_LT(lit.direct_radiance[i], 1e-3 * peak) << "pixel " << lit.cloud.pixels[i];
  }
  EXPECT_GT(far_pixels, lit.cloud.size() / 2);
  const double worst = WorstError(lit, s.light, s.camera);
  std::printf("polished metal: peak %.4g W/(m^2 sr), worst error vs the CPU %.2f of the tolerance\n", peak, worst);
  EXPECT_LT(worst, 1.0);
}

TEST_P(RasterDirectLightTest, RoughPlasticUnderAnOffsetProjectorIsDarkOutsideItsCone) {
  LitScene s;
  s.AddPlane(Eigen::Vector3d(0, 0, 1.5), 1.5, Tilt(-20, 30), 4);
  s.materials.assign(5, Lambertian(0.5));
  s.materials[4] = {0.3, 0.0, 0.6, 0.04};
  s.light.emitter.position = Eigen::Vector3d(0.15, 0.02, 0.0);
  s.light.emitter.axis = Eigen::Vector3d(-0.1, 0.05, 1.0);
  s.light.emitter.cone_half_angle_rad = 12 * std::numbers::pi / 180;
  s.light.emitter.radiant_intensity_w_per_sr = 0.5;
  const LitCloud lit = ScanLit(s, GetParam(), Key("plastic"));
  ASSERT_GT(lit.cloud.size(), s.camera.pixel_count() / 2);
  const Eigen::Vector3d axis = s.light.emitter.axis.normalized();
  const auto cone_angle_deg = [&](size_t i) {
    const Eigen::Vector3d from_emitter =
        (lit.cloud.positions[i].cast<double>() - s.light.emitter.position).normalized();
    return std::acos(std::clamp(from_emitter.dot(axis), -1.0, 1.0)) * 180 / std::numbers::pi;
  };
  size_t inside = 0, outside = 0;
  for (size_t i = 0; i < lit.cloud.size(); ++i) {
    const double angle_deg = cone_angle_deg(i);
    if (angle_deg > 12.5) {
      ++outside;
      EXPECT_EQ(lit.direct_radiance[i], 0.0f) << "pixel " << lit.cloud.pixels[i];
    } else if (angle_deg < 11.5) {
      ++inside;
      EXPECT_GT(lit.direct_radiance[i], 0.0f) << "pixel " << lit.cloud.pixels[i];
    }
  }
  EXPECT_GT(inside, lit.cloud.size() / 20);
  EXPECT_GT(outside, lit.cloud.size() / 20);
  // Pixels on the cone's rim may fall either side in float and double; away from it they agree.
  const double worst =
      WorstError(lit, s.light, s.camera, [&](size_t i) { return std::abs(cone_angle_deg(i) - 12) < 0.5; });
  std::printf("rough plastic: %zu pixels inside the cone, %zu outside, worst error %.2f of the tolerance\n", inside,
              outside, worst);
  EXPECT_LT(worst, 1.0);
}

TEST_P(RasterDirectLightTest, EachObjectShowsItsOwnMaterialInOneFrame) {
  LitScene s;
  s.AddPlane(Eigen::Vector3d(-0.35, 0, 1.3), 0.3, Tilt(10, 20), 3);   // white Lambertian
  s.AddPlane(Eigen::Vector3d(0.35, 0, 1.1), 0.3, Tilt(-20, -55), 5);  // a rough, weakly specular plastic
  s.AddPlane(Eigen::Vector3d(0, 0.3, 1.6), 0.25, Tilt(5, 0), 9);     // past the table: the default
  s.materials.assign(6, Lambertian(0.1));
  s.materials[3] = Lambertian(0.9);
  s.materials[5] = {0.25, 0.0, 0.45, 0.01};  // F0 < 0.02: Schlick's F90 = 50 F0 below 1
  s.light.default_material = {0.5, 1.0, 0.3, 0.04};  // a brushed metal
  const LitCloud lit = ScanLit(s, GetParam(), Key("three"));
  size_t of_id[10] = {};
  for (size_t i = 0; i < lit.cloud.size(); ++i) {
    ++of_id[lit.cloud.instance_ids[i]];
    EXPECT_GT(lit.direct_radiance[i], 0.0f);
  }
  EXPECT_GT(of_id[3], 1000u);
  EXPECT_GT(of_id[5], 1000u);
  EXPECT_GT(of_id[9], 1000u);
  const double worst = WorstError(lit, s.light, s.camera);
  std::printf("three materials: worst error vs the CPU %.2f of the tolerance\n", worst);
  EXPECT_LT(worst, 1.0);
}

// The lit programs draw the same geometry, and a lit scan leaves nothing behind that changes the
// plain scans after it (the radiance attachment is detached, the plain programs bound again).
TEST_P(RasterDirectLightTest, PlainScansAroundALitOneGiveTheSamePoints) {
  LitScene s;
  s.AddPlane(Eigen::Vector3d(0, 0, 1.4), 0.8, Tilt(20, 10), 1);
  s.materials = {Lambertian(0.5), Lambertian(0.5)};
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  RasterOptions options;
  options.fields = kFieldPosition | kFieldPixel;
  const auto plain = [&] {
    auto cloud = RasterScan(*renderer, Key("around"), s.instances, s.camera, s.world_from_sensor, GetParam(), options);
    EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
    return cloud.ok() ? std::move(*cloud) : PointCloud{};
  };
  const PointCloud before = plain();
  s.light.materials = s.materials;
  auto lit = RasterScanLit(*renderer, Key("around"), s.instances, s.camera, s.world_from_sensor, GetParam(), s.light,
                           options);
  ASSERT_TRUE(lit.ok()) << lit.status().ToString();
  const PointCloud after = plain();
  ASSERT_GT(before.size(), 1000u);
  ASSERT_EQ(after.size(), before.size());
  ASSERT_EQ(lit->cloud.size(), before.size());
  EXPECT_EQ(lit->direct_radiance.size(), before.size());
  EXPECT_TRUE(after.positions == before.positions);
  EXPECT_TRUE(lit->cloud.positions == before.positions);
  EXPECT_TRUE(lit->cloud.pixels == before.pixels);
}

INSTANTIATE_TEST_SUITE_P(Methods, RasterDirectLightTest,
                         ::testing::Values(RasterMethod::kDepthBuffer, RasterMethod::kColourBuffer),
                         [](const auto& info) {
                           return info.param == RasterMethod::kDepthBuffer ? "Depth" : "Colour";
                         });

}  // namespace
}  // namespace vscan::raster
