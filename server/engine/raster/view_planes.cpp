#include "raster/view_planes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vscan::raster {
namespace {

// Hugging planes sit this far outside the box (fractions of its depth extent and of its far
// depth), so faces lying on the box are not clipped.
constexpr double kExtentMargin = 1e-3;
constexpr double kDepthMargin = 1e-4;

}  // namespace

double MaxRayLength(const sensor::PinholeCamera& camera) {
  double longest = 1.0;
  for (uint32_t u : {0u, camera.width - 1}) {
    for (uint32_t v : {0u, camera.height - 1}) {
      longest = std::max(longest, static_cast<double>(camera.RayThroughPixel(u, v).norm()));
    }
  }
  return longest;
}

ViewPlanes PlanesForScene(const sensor::PinholeCamera& camera, const Pose3& world_from_sensor,
                          const Eigen::AlignedBox3d& world_box, bool hug) {
  ViewPlanes planes;
  planes.near = camera.near;
  planes.far = camera.far;
  planes.near_range = camera.near;
  planes.far_range = camera.far * MaxRayLength(camera);
  if (world_box.isEmpty()) {
    planes.empty = true;
    return planes;
  }
  if (!hug) return planes;

  const Pose3 sensor_from_world = world_from_sensor.inverse();
  const Eigen::Vector3d eye = world_from_sensor.translation();
  double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min, farthest = 0;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner = world_box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
    const double z = (sensor_from_world * corner).z();
    z_min = std::min(z_min, z);
    z_max = std::max(z_max, z);
    farthest = std::max(farthest, (corner - eye).norm());
  }
  const double margin = std::max(kExtentMargin * (z_max - z_min), kDepthMargin * std::abs(z_max));
  planes.near = std::max(camera.near, z_min - margin);
  planes.far = std::min(camera.far, z_max + margin);
  if (planes.near >= planes.far) {
    planes.empty = true;
    return planes;
  }
  planes.near_range = std::max(planes.near, world_box.exteriorDistance(eye));
  planes.far_range = std::min(planes.far * MaxRayLength(camera), farthest);
  if (planes.far_range <= planes.near_range) planes.far_range = planes.near_range * (1 + 1e-6) + 1e-9;
  return planes;
}

Eigen::Matrix4d ClipFromSensor(const sensor::PinholeCamera& camera, double near, double far, bool reversed,
                               bool zero_to_one) {
  const double w = camera.width, h = camera.height, span = far - near;
  // d * z = a * z + b
  const double a = reversed ? -near / span : far / span;
  const double b = reversed ? near * far / span : -near * far / span;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = 2 * camera.fx / w;
  m(0, 2) = 2 * camera.cx / w - 1;
  m(1, 1) = 2 * camera.fy / h;
  m(1, 2) = 2 * camera.cy / h - 1;
  m(2, 2) = zero_to_one ? a : 2 * a - 1;
  m(2, 3) = zero_to_one ? b : 2 * b;
  m(3, 2) = 1;
  return m;
}

}  // namespace vscan::raster
