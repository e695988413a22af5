#include "capture/outlier_rays.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "capture/pixel_draws.h"
#include "raycast/ray_queries.h"

namespace vscan::capture {
namespace {

// Uniform over the solid angle of the cone of half-angle max_angle around unit axis d.
Eigen::Vector3d TiltWithinCone(const Eigen::Vector3d& d, double max_angle, PixelDraws& draws) {
  const double cos_theta = 1.0 - draws.Uniform() * (1.0 - std::cos(max_angle));
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * std::numbers::pi * draws.Uniform();
  const Eigen::Vector3d helper = std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d a = d.cross(helper).normalized();
  const Eigen::Vector3d b = d.cross(a);
  return (cos_theta * d + sin_theta * (std::cos(phi) * a + std::sin(phi) * b)).normalized();
}

// Uniform within the ball of the given radius.
Eigen::Vector3d OffsetWithinBall(double radius, PixelDraws& draws) {
  const double z = 2.0 * draws.Uniform() - 1.0;
  const double phi = 2.0 * std::numbers::pi * draws.Uniform();
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double r = radius * std::cbrt(draws.Uniform());
  return r * Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z);
}

}  // namespace

OutlierCounts CastOutliers(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                           const Pose3& world_from_sensor, const PointCloud& clean, const MeasurementSpec& spec,
                           float max_distance, std::vector<uint8_t>& status,
                           std::vector<Eigen::Vector3f>& measured) {
  const OutlierSpec& o = spec.outliers;
  const double max_angle = o.angle_deg * std::numbers::pi / 180.0;
  const Eigen::Matrix3d rotation = world_from_sensor.linear();
  const Eigen::Vector3d centre = world_from_sensor.translation();

  // The pick draw of every measured pixel in parallel, the rays of the (few) picked ones after.
  std::vector<uint8_t> pick(clean.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, clean.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (status[i] != static_cast<uint8_t>(PointStatus::kMeasured)) continue;
      pick[i] = PixelDraws(spec.seed, DrawStream::kOutlierPick, clean.pixels[i]).Uniform() < o.rate;
    }
  });
  std::vector<size_t> picked;
  std::vector<Eigen::Vector3f> origins, directions;
  for (size_t i = 0; i < clean.size(); ++i) {
    if (!pick[i]) continue;
    const uint32_t pixel = clean.pixels[i];
    PixelDraws draws(spec.seed, DrawStream::kOutlierRay, pixel);
    const Eigen::Vector3d ray =
        camera.RayThroughPixel(pixel % camera.width, pixel / camera.width).cast<double>().normalized();
    Eigen::Vector3d direction = max_angle > 0 ? TiltWithinCone(ray, max_angle, draws) : ray;
    Eigen::Vector3d origin = o.origin_m > 0 ? OffsetWithinBall(o.origin_m, draws) : Eigen::Vector3d::Zero();
    picked.push_back(i);
    origins.push_back((centre + rotation * origin).cast<float>());
    directions.push_back((rotation * direction).cast<float>());
  }

  const std::vector<raycast::RayHit> hits = raycast::IntersectRays(scene, origins, directions, 0.0f, max_distance);
  const Pose3 sensor_from_world = world_from_sensor.inverse();
  OutlierCounts counts;
  for (size_t k = 0; k < picked.size(); ++k) {
    const size_t i = picked[k];
    const Eigen::Vector3d world = origins[k].cast<double>() + directions[k].cast<double>() * hits[k].distance;
    const Eigen::Vector3d point = sensor_from_world * world;
    // The sensor reports no depth outside its range, wherever the light came from.
    if (!hits[k].hit || point.z() < camera.near || point.z() > camera.far) {
      status[i] = static_cast<uint8_t>(PointStatus::kUnspecified);
      ++counts.missed;
      continue;
    }
    measured[i] = point.cast<float>();
    status[i] = static_cast<uint8_t>(PointStatus::kOutlier);
    ++counts.outliers;
  }
  return counts;
}

}  // namespace vscan::capture
