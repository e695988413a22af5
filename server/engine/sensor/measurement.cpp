#include "sensor/measurement.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "random/seeded_draws.h"

namespace vscan::sensor {
namespace {

Status CheckFinite(double value, std::string_view field, std::string_view member) {
  if (!std::isfinite(value)) return InvalidArgument(FieldPath(field, member), "NaN or infinite value");
  return Status::Ok();
}

Status CheckNonNegative(double value, std::string_view field, std::string_view member) {
  RETURN_IF_ERROR(CheckFinite(value, field, member));
  if (value < 0) return InvalidArgument(FieldPath(field, member), "must be >= 0");
  return Status::Ok();
}

Eigen::Vector3d Distort(const Eigen::Vector3d& p, const LensDistortion& d) {
  if (!(p.z() > 0)) return p;
  const double x = p.x() / p.z(), y = p.y() / p.z();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
  return {xd * p.z(), yd * p.z(), p.z()};
}

Eigen::Vector3d AddNoise(const Eigen::Vector3d& p, const DepthNoise& n, random::KeyedNormals& normals) {
  const double z = p.z();
  const double sigma = std::max(0.0, n.sigma_a + n.sigma_b * z + n.sigma_c * z * z);
  if (n.along_ray) {
    const double length = p.norm();
    const double step = sigma * normals.Next();
    return length > 0 ? Eigen::Vector3d(p * (1 + step / length)) : p;
  }
  const double dx = normals.Next(), dy = normals.Next(), dz = normals.Next();
  return p + sigma * Eigen::Vector3d(dx, dy, dz);
}

// False when the quantised depth is not positive.
bool Quantise(Eigen::Vector3d& p, double step) {
  const double zq = std::round(p.z() / step) * step;
  if (!(zq > 0) || !(p.z() > 0)) return false;
  const double scale = zq / p.z();
  p = Eigen::Vector3d(p.x() * scale, p.y() * scale, zq);
  return true;
}

Status CheckArray(size_t size, size_t n, bool present, std::string_view name) {
  if (present && size != n) {
    return InvalidArgument("cloud." + std::string(name) + ": " + std::to_string(size) + " values for " +
                           std::to_string(n) + " points");
  }
  return Status::Ok();
}

template <typename T>
void Compact(std::vector<T>& values, const std::vector<uint8_t>& keep) {
  if (values.size() != keep.size()) return;
  size_t out = 0;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (keep[i]) values[out++] = values[i];
  }
  values.resize(out);
}

}  // namespace

Status ValidateDistortion(const LensDistortion& d, std::string_view field) {
  RETURN_IF_ERROR(CheckFinite(d.k1, field, "k1"));
  RETURN_IF_ERROR(CheckFinite(d.k2, field, "k2"));
  RETURN_IF_ERROR(CheckFinite(d.k3, field, "k3"));
  RETURN_IF_ERROR(CheckFinite(d.p1, field, "p1"));
  return CheckFinite(d.p2, field, "p2");
}

Status ValidateNoise(const DepthNoise& n, std::string_view field) {
  RETURN_IF_ERROR(CheckNonNegative(n.sigma_a, field, "sigma_a"));
  RETURN_IF_ERROR(CheckNonNegative(n.sigma_b, field, "sigma_b"));
  RETURN_IF_ERROR(CheckNonNegative(n.sigma_c, field, "sigma_c"));
  RETURN_IF_ERROR(CheckNonNegative(n.depth_step, field, "depth_step_m"));
  return CheckNonNegative(n.min_intensity, field, "min_intensity");
}

bool MeasurePoint(Eigen::Vector3d& p, const LensDistortion& distortion, const DepthNoise& noise, uint64_t seed,
                  uint64_t key) {
  if (distortion.any()) p = Distort(p, distortion);
  if (noise.sigma_a > 0 || noise.sigma_b > 0 || noise.sigma_c > 0) {
    random::KeyedNormals normals(seed, key);
    p = AddNoise(p, noise, normals);
  }
  if (noise.depth_step > 0 && !Quantise(p, noise.depth_step)) return false;
  // Huge (finite) sigmas or distortion coefficients can push a point, or its range, beyond single precision.
  return std::isfinite(p.cast<float>().squaredNorm());
}

Status ApplyMeasurementModel(PointCloud& cloud, const LensDistortion& distortion, const DepthNoise& noise,
                             uint64_t seed) {
  RETURN_IF_ERROR(ValidateDistortion(distortion, "distortion"));
  RETURN_IF_ERROR(ValidateNoise(noise, "noise"));
  const size_t n = cloud.size();
  RETURN_IF_ERROR(CheckArray(cloud.normals.size(), n, cloud.Has(kFieldNormal), "normals"));
  RETURN_IF_ERROR(CheckArray(cloud.ranges.size(), n, cloud.Has(kFieldRange), "ranges"));
  RETURN_IF_ERROR(CheckArray(cloud.intensities.size(), n, cloud.Has(kFieldIntensity), "intensities"));
  RETURN_IF_ERROR(CheckArray(cloud.instance_ids.size(), n, cloud.Has(kFieldInstanceId), "instance_ids"));
  RETURN_IF_ERROR(CheckArray(cloud.pixels.size(), n, cloud.Has(kFieldPixel), "pixels"));
  if (!distortion.any() && !noise.any()) return Status::Ok();

  const bool dim_filter = noise.min_intensity > 0 && cloud.Has(kFieldIntensity);
  const bool moves = distortion.any() || noise.sigma_a > 0 || noise.sigma_b > 0 || noise.sigma_c > 0 ||
                     noise.depth_step > 0;
  const bool by_pixel = cloud.Has(kFieldPixel);
  std::vector<uint8_t> keep(n, 1);
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3d p = cloud.positions[i].cast<double>();
    if (moves && !MeasurePoint(p, distortion, noise, seed, by_pixel ? cloud.pixels[i] : i)) keep[i] = 0;
    if (dim_filter && !(cloud.intensities[i] >= noise.min_intensity)) keep[i] = 0;
    if (moves) {
      cloud.positions[i] = p.cast<float>();
      if (cloud.Has(kFieldRange)) cloud.ranges[i] = static_cast<float>(p.norm());
    }
    kept += keep[i];
  }
  if (kept == n) return Status::Ok();
  Compact(cloud.positions, keep);
  Compact(cloud.normals, keep);
  Compact(cloud.ranges, keep);
  Compact(cloud.intensities, keep);
  Compact(cloud.instance_ids, keep);
  Compact(cloud.pixels, keep);
  return Status::Ok();
}

}  // namespace vscan::sensor
