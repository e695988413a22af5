// The ray caster and both raster methods on the same scene (the bunny behind a sphere): same pixel
// coverage except on silhouettes, depths within each method's quantisation, same instance ids.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "raster/raster_scanner.h"
#include "raster/view_planes.h"
#include "raster_test_scenes.h"
#include "vscan_test/meshes.h"
#include "raycast/scanner.h"

namespace vscan::raster {
namespace {

constexpr uint32_t kBunnyId = 1, kSphereId = 2;
// Coverage may differ only where a pixel centre falls within rounding of a silhouette edge.
constexpr double kMaxCoverageMismatch = 0.002;
// Pixels on a triangle edge may take the neighbouring face's normal in one backend.
constexpr double kMaxNormalMismatch = 0.01;
// The ray caster's own single-precision error, relative to depth.
constexpr double kRaycastRelativeError = 2e-6;
// Rasterisers snap vertices to a sub-pixel grid (8 bits on llvmpipe and most GPUs), which moves a
// sloped surface's depth at a pixel centre by up to its slope times one grid step.
constexpr double kSubpixelStep = 1.0 / 256;

struct Scene {
  std::vector<raycast::SceneInstance> instances;
  sensor::PinholeCamera camera;
  Pose3 world_from_sensor;
};

Scene MakeScene() {
  Scene s;
  Eigen::Vector3f lo, hi;
  testing::Bunny()->Bounds(lo, hi);
  raycast::SceneInstance bunny;
  bunny.mesh = testing::Bunny();
  bunny.instance_id = kBunnyId;
  bunny.world_from_object = Pose3(Eigen::Translation3d(-(0.5f * (lo + hi)).cast<double>()));
  raycast::SceneInstance sphere;
  sphere.mesh = vscan::test::Share(vscan::test::MakeUvSphere(0.05, 48, 96));
  sphere.instance_id = kSphereId;
  sphere.world_from_object = Pose3(Eigen::Translation3d(0.06, -0.02, 0.12));
  s.instances = {bunny, sphere};
  s.camera = sensor::CameraFromFov(640, 480, 32.0, 0.05, 10.0);
  s.camera.lighting = {1.0, 1.0, 0.5, 0.25};
  s.world_from_sensor = *PoseFromLookAt({0.15, 0.1, 0.55}, {0, 0, 0}, Eigen::Vector3d::UnitY(), "test");
  return s;
}

// Per-pixel view of a cloud: index of the pixel's point or -1.
struct Image {
  const PointCloud* cloud = nullptr;
  std::vector<int64_t> index;
  int64_t At(const sensor::PinholeCamera& c, int64_t u, int64_t v) const {
    if (u < 0 || v < 0 || u >= c.width || v >= c.height) return -1;
    return index[static_cast<size_t>(v * c.width + u)];
  }
};

// True where the ray-cast image changes around (u, v): coverage, instance, or a depth jump.
bool OnEdge(const Image& ray, const sensor::PinholeCamera& c, int64_t u, int64_t v) {
  const int64_t centre = ray.At(c, u, v);
  for (int64_t dv = -1; dv <= 1; ++dv) {
    for (int64_t du = -1; du <= 1; ++du) {
      const int64_t n = ray.At(c, u + du, v + dv);
      if ((n < 0) != (centre < 0)) return true;
      if (n < 0) continue;
      const PointCloud& p = *ray.cloud;
      if (p.instance_ids[n] != p.instance_ids[centre]) return true;
      if (std::abs(p.positions[n].z() - p.positions[centre].z()) > 0.02 * p.positions[centre].z()) return true;
    }
  }
  return false;
}

// Largest depth change per pixel around (u, v) in the ray-cast image (central differences).
double DepthSlope(const Image& ray, const sensor::PinholeCamera& c, int64_t u, int64_t v) {
  const auto z = [&](int64_t du, int64_t dv) { return ray.cloud->positions[ray.At(c, u + du, v + dv)].z(); };
  return std::max(std::abs(z(1, 0) - z(-1, 0)), std::abs(z(0, 1) - z(0, -1))) / 2;
}

struct Agreement {
  size_t covered = 0, coverage_mismatch = 0, off_edge_mismatch = 0;
  size_t compared = 0, id_mismatch = 0, normal_mismatch = 0, depth_outliers = 0, intensity_outliers = 0;
  double worst_depth_ratio = 0;  // worst |dz| / allowed
  double rms_dz = 0;
};

struct AgreementCase {
  RasterMethod method;
  DepthFormat format;
  const char* name;
};

class BackendAgreementTest : public ::testing::TestWithParam<AgreementCase> {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(MakeScene());
    auto built = raycast::RaycastScene::Build(scene_->instances);
    ASSERT_TRUE(built.ok()) << built.status().ToString();
    raycast::ScanOptions options;
    options.fields = kFieldsAll;
    options.frame = raycast::ScanFrame::kSensor;
    auto cloud = raycast::Scan(**built, scene_->camera, scene_->world_from_sensor, options);
    ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
    ray_cloud_ = new PointCloud(std::move(*cloud));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete ray_cloud_;
  }
  static Scene* scene_;
  static PointCloud* ray_cloud_;
};

Scene* BackendAgreementTest::scene_ = nullptr;
PointCloud* BackendAgreementTest::ray_cloud_ = nullptr;

TEST_P(BackendAgreementTest, MatchesTheRayCaster) {
  RasterRenderer* renderer = testing::SharedRenderer();
  ASSERT_NE(renderer, nullptr);
  ASSERT_FALSE(testing::Bunny()->empty());
  const Scene& s = *scene_;
  const RasterMethod method = GetParam().method;
  RasterOptions options;
  options.depth_format = GetParam().format;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  RasterStats stats;
  auto cloud = RasterScan(*renderer, "bunny+sphere", s.instances, s.camera, s.world_from_sensor, method, options, &stats);
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();

  const Image ray{ray_cloud_, testing::PointOfPixel(*ray_cloud_, s.camera)};
  const Image raster{&*cloud, testing::PointOfPixel(*cloud, s.camera)};
  const bool depth_method = method == RasterMethod::kDepthBuffer;
  const double range_step = (stats.far_range - stats.near_range) / 65535.0;
  const sensor::Lighting& light = s.camera.lighting;
  // The colour method's intensity is 8 bits of the largest possible one.
  const double intensity_step =
      depth_method ? 0.0 : light.power / (light.constant + (light.linear + light.quadratic * stats.near_range) * stats.near_range) / 255;
  Agreement a;
  double sum_dz2 = 0;
  for (int64_t v = 0; v < s.camera.height; ++v) {
    for (int64_t u = 0; u < s.camera.width; ++u) {
      const int64_t r = ray.At(s.camera, u, v), g = raster.At(s.camera, u, v);
      a.covered += r >= 0 || g >= 0;
      const bool edge = OnEdge(ray, s.camera, u, v);
      if ((r >= 0) != (g >= 0)) {
        ++a.coverage_mismatch;
        a.off_edge_mismatch += !edge;
        continue;
      }
      if (r < 0 || edge) continue;
      ++a.compared;
      a.id_mismatch += ray_cloud_->instance_ids[r] != cloud->instance_ids[g];
      const float normal_dot = ray_cloud_->normals[r].dot(cloud->normals[g]);
      a.normal_mismatch += normal_dot < 0.9999f;
      // A neighbouring face's normal (pixel centres on a shared edge) changes the cosine by at most
      // the angle between the normals.
      const double normal_angle = 2 * std::asin(std::min(1.0f, (ray_cloud_->normals[r] - cloud->normals[g]).norm() / 2));
      const double range = ray_cloud_->ranges[r];
      const double allowed_intensity = light.power * normal_angle / (light.constant + (light.linear + light.quadratic * range) * range) +
                                       0.5 * intensity_step + 1e-5;
      a.intensity_outliers += std::abs(ray_cloud_->intensities[r] - cloud->intensities[g]) > allowed_intensity;
      const double z = ray_cloud_->positions[r].z();
      const double dz = std::abs(cloud->positions[g].z() - z);
      // Within the raster method's quantisation (as in raster_plane_test) plus the ray caster's error.
      double allowed = kRaycastRelativeError * z + kSubpixelStep * DepthSlope(ray, s.camera, u, v);
      if (depth_method && GetParam().format == DepthFormat::kFloat32Reversed) {
        const float d = static_cast<float>(stats.near * (stats.far - z) / (z * (stats.far - stats.near)));
        allowed += 10 * (std::nextafter(d, 2.0f) - d) * DepthPerUnitD(z, stats.near, stats.far);
      } else if (depth_method) {
        allowed += 5 / 16777215.0 * DepthPerUnitD(z, stats.near, stats.far);
      } else {
        allowed += range_step * z / ray_cloud_->ranges[r];
      }
      a.worst_depth_ratio = std::max(a.worst_depth_ratio, dz / allowed);
      a.depth_outliers += dz > allowed;
      sum_dz2 += dz * dz;
    }
  }
  a.rms_dz = std::sqrt(sum_dz2 / static_cast<double>(std::max<size_t>(a.compared, 1)));
  std::printf("%s: %zu pixels covered, %zu coverage mismatches (%zu off silhouettes), %zu compared, %zu id / %zu normal "
              "mismatches, depth |dz| rms %.3g m, worst %.3f of allowed, planes [%.4f, %.4f]\n",
              GetParam().name, a.covered, a.coverage_mismatch, a.off_edge_mismatch,
              a.compared, a.id_mismatch, a.normal_mismatch, a.rms_dz, a.worst_depth_ratio, stats.near, stats.far);

  EXPECT_GT(a.compared, 50000u) << "the scene should fill a good part of the frame";
  EXPECT_EQ(a.off_edge_mismatch, 0u);
  EXPECT_LE(static_cast<double>(a.coverage_mismatch), kMaxCoverageMismatch * static_cast<double>(a.covered));
  EXPECT_EQ(a.id_mismatch, 0u);
  EXPECT_EQ(a.depth_outliers, 0u);
  EXPECT_LE(static_cast<double>(a.normal_mismatch), kMaxNormalMismatch * static_cast<double>(a.compared));
  EXPECT_EQ(a.intensity_outliers, 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Methods, BackendAgreementTest,
    ::testing::Values(AgreementCase{RasterMethod::kDepthBuffer, DepthFormat::kFloat32Reversed, "DepthFloat32Reversed"},
                      AgreementCase{RasterMethod::kDepthBuffer, DepthFormat::kFixed24, "DepthFixed24"},
                      AgreementCase{RasterMethod::kColourBuffer, DepthFormat::kFloat32Reversed, "Colour"}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace vscan::raster
