#include "service/datasets/format/view_poses.h"

#include <cmath>
#include <numbers>

namespace vscan::service::dataset {
namespace {

uint64_t SplitMix(uint64_t& state) {
  uint64_t x = (state += 0x9e3779b97f4a7c15ull);
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from the top 53 bits.
double Unit(uint64_t& state) { return double(SplitMix(state) >> 11) * 0x1.0p-53; }

}  // namespace

uint64_t ViewPoseSeed(uint64_t scene_seed, uint32_t view) {
  uint64_t state = scene_seed ^ 0x5c3f1e0b7a4d2986ull;
  state += view;
  return SplitMix(state);
}

Pose3 SampleViewPose(const DatasetPlan& plan, uint64_t view_seed) {
  uint64_t state = view_seed;
  const auto [nearest_m, farthest_m] = ViewDistanceRange(plan);
  // Uniform over the spherical cap: cos(tilt) uniform in [cos(cone), 1].
  const double cos_cone = std::cos(plan.views.cone_deg * std::numbers::pi / 180.0);
  const double cos_tilt = 1.0 - Unit(state) * (1.0 - cos_cone);
  const double azimuth = 2.0 * std::numbers::pi * Unit(state);
  const double distance = nearest_m + Unit(state) * (farthest_m - nearest_m);
  const double sin_tilt = std::sqrt(std::max(0.0, 1.0 - cos_tilt * cos_tilt));
  Pose3 bin_from_camera = Pose3::Identity();
  if (sin_tilt == 0.0) {
    bin_from_camera.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    bin_from_camera.translation() = Eigen::Vector3d(0, 0, distance);
    return bin_from_camera;
  }
  const Eigen::Vector3d towards_camera(sin_tilt * std::cos(azimuth), sin_tilt * std::sin(azimuth), cos_tilt);
  const Eigen::Vector3d forward = -towards_camera;
  // Image x along the bin's x as far as the tilt allows; the cone's bound keeps it off the axis.
  const Eigen::Vector3d right = (Eigen::Vector3d::UnitX() - forward.x() * forward).normalized();
  bin_from_camera.linear().col(0) = right;
  bin_from_camera.linear().col(1) = forward.cross(right);
  bin_from_camera.linear().col(2) = forward;
  bin_from_camera.translation() = distance * towards_camera;
  return bin_from_camera;
}

}  // namespace vscan::service::dataset
