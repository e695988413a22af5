#include "capture/indirect_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <tbb/parallel_for.h>

#include "capture/pixel_draws.h"
#include "raycast/ray_queries.h"
#include "sensor/brdf.h"
#include "sensor/pixel_radiometry.h"

namespace vscan::capture {
namespace {

constexpr int32_t kNone = -1;
// Grid pixels count as the same surface as a pixel within these bounds.
constexpr double kSameSurfaceCos = 0.9;          // normals within about 26 degrees
constexpr double kSameSurfaceRelativeGap = 0.01;  // off the pixel's plane by 1% of its range

// Duff et al.'s branchless orthonormal basis ("Building an orthonormal basis, revisited", 2017).
void TangentsOf(const Eigen::Vector3d& n, Eigen::Vector3d& t, Eigen::Vector3d& b) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double c = n.x() * n.y() * a;
  t = Eigen::Vector3d(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Eigen::Vector3d(c, sign + n.y() * n.y() * a, -n.y());
}

class IndirectTracer {
 public:
  IndirectTracer(const raycast::RaycastScene& scene, const Pose3& world_from_sensor, const PointCloud& clean,
                 const ReturnedLightSpec& spec, uint64_t seed)
      : scene_(scene), world_from_sensor_(world_from_sensor), rotation_(world_from_sensor.linear()), clean_(clean),
        spec_(spec), seed_(seed),
        wavenumber_(2 * std::numbers::pi * spec.modulation_frequency_hz / sensor::kSpeedOfLightMs),
        has_ids_(clean.Has(kFieldInstanceId)) {}

  const sensor::Material& MaterialOf(uint32_t id) const {
    return id != 0 && id < spec_.materials.size() ? spec_.materials[id] : spec_.default_material;
  }

  // Monte Carlo over cosine-weighted directions at x1: with pdf cos / pi, each sample's estimate of
  // the radiance to the camera is pi f(l, v) L_in(l).
  IndirectReturn Trace(size_t i) const {
    const Eigen::Vector3d x1 = clean_.positions[i].cast<double>();
    Eigen::Vector3d n1 = clean_.normals[i].cast<double>().normalized();
    if (n1.dot(x1) > 0) n1 = -n1;
    const double range = x1.norm();
    if (!(range > 0) || !n1.allFinite()) return {};
    const Eigen::Vector3d to_camera = -x1 / range;
    const sensor::Material& m1 = MaterialOf(has_ids_ ? clean_.instance_ids[i] : 0);
    const double direct_legs = (spec_.emitter.position - x1).norm();
    Eigen::Vector3d t, b;
    TangentsOf(n1, t, b);
    const double epsilon = 1e-5 * (1.0 + range);
    const Eigen::Vector3f origin_world = (world_from_sensor_ * (x1 + epsilon * n1)).cast<float>();
    PixelDraws draws(seed_, DrawStream::kIndirectLight, clean_.pixels[i]);
    double radiance = 0;
    std::complex<double> phasor{0, 0};
    for (uint32_t s = 0; s < spec_.indirect_samples; ++s) {
      const double u1 = draws.Uniform(), u2 = draws.Uniform();
      const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
      const Eigen::Vector3d l = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0 - u1) * n1;
      const raycast::RayHit hit = raycast::IntersectRay(scene_, origin_world, (rotation_ * l).cast<float>(), 0.0f,
                                                        std::numeric_limits<float>::infinity());
      if (!hit.hit) continue;
      const Eigen::Vector3d x2 = x1 + epsilon * n1 + static_cast<double>(hit.distance) * l;
      const Eigen::Vector3d n2 = rotation_.transpose() * hit.normal.cast<double>();
      const double lit = sensor::DirectRadiance(MaterialOf(hit.instance_id), x2, n2, spec_.emitter, x1);
      if (!(lit > 0)) continue;
      const double brdf = sensor::EvaluateBrdf(m1, n1, l, to_camera);
      if (!(brdf > 0)) continue;
      const double emitter_leg = (spec_.emitter.position - x2).norm();
      const float margin = static_cast<float>(1e-5 * (1.0 + emitter_leg));
      if (raycast::SegmentOccluded(scene_, (world_from_sensor_ * x2).cast<float>(),
                                   (world_from_sensor_ * spec_.emitter.position).cast<float>(), margin)) {
        continue;
      }
      const double estimate = std::numbers::pi * brdf * lit;
      radiance += estimate;
      const double excess = emitter_leg + static_cast<double>(hit.distance) - direct_legs;
      phasor += estimate * std::polar(1.0, wavenumber_ * excess);
    }
    const double n = static_cast<double>(spec_.indirect_samples);
    return {radiance / n, phasor / n};
  }

 private:
  const raycast::RaycastScene& scene_;
  const Pose3& world_from_sensor_;
  const Eigen::Matrix3d rotation_;
  const PointCloud& clean_;
  const ReturnedLightSpec& spec_;
  const uint64_t seed_;
  const double wavenumber_;
  const bool has_ids_;
};

bool SameSurface(const PointCloud& clean, size_t pixel, size_t grid) {
  if (clean.Has(kFieldInstanceId) && clean.instance_ids[pixel] != clean.instance_ids[grid]) return false;
  const Eigen::Vector3f& n = clean.normals[pixel];
  if (std::abs(n.dot(clean.normals[grid])) < kSameSurfaceCos * n.norm() * clean.normals[grid].norm()) return false;
  const float gap = std::abs(n.normalized().dot(clean.positions[grid] - clean.positions[pixel]));
  return gap <= kSameSurfaceRelativeGap * clean.positions[pixel].norm();
}

}  // namespace

uint64_t IndirectGridSamples(const sensor::PinholeCamera& camera, const ReturnedLightSpec& spec) {
  const uint64_t stride = std::max<uint32_t>(1, spec.indirect_stride_px);
  return uint64_t{spec.indirect_samples} * ((camera.width + stride - 1) / stride) *
         ((camera.height + stride - 1) / stride);
}

StatusOr<std::vector<IndirectReturn>> IndirectReturns(const raycast::RaycastScene& scene,
                                                      const Pose3& world_from_sensor,
                                                      const sensor::PinholeCamera& camera, const PointCloud& clean,
                                                      const ReturnedLightSpec& spec, uint64_t seed,
                                                      const std::vector<uint8_t>& wanted,
                                                      const std::atomic<bool>* cancel, uint64_t max_samples) {
  const size_t n = clean.size();
  std::vector<IndirectReturn> out(n);
  if (spec.indirect_samples == 0 || n == 0) return out;
  const auto cancelled = [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  const IndirectTracer tracer(scene, world_from_sensor, clean, spec, seed);
  const uint32_t stride = std::max<uint32_t>(1, spec.indirect_stride_px);
  const uint32_t width = std::max<uint32_t>(1, camera.width);
  const auto on_grid = [&](size_t i) {
    const uint32_t p = clean.pixels[i];
    return (p % width) % stride == 0 && (p / width) % stride == 0;
  };
  const auto needed = [&](size_t i) { return wanted.empty() || wanted[i] != 0; };
  // A grid pixel is traced only when a wanted pixel may interpolate from it: one in the (up to four)
  // cells of the grid it is a corner of.
  const uint64_t cells_x = (width + stride - 1) / stride, cells_y = (camera.height + stride - 1) / stride;
  std::vector<uint8_t> cell_wanted;
  if (!wanted.empty()) {
    cell_wanted.assign(cells_x * cells_y, 0);
    for (size_t i = 0; i < n; ++i) {
      const uint64_t cell = uint64_t{clean.pixels[i] / width / stride} * cells_x + clean.pixels[i] % width / stride;
      if (wanted[i] && cell < cell_wanted.size()) cell_wanted[cell] = 1;
    }
  }
  const auto grid_needed = [&](size_t i) {
    if (cell_wanted.empty()) return true;
    if (stride == 1) return wanted[i] != 0;  // no pixel interpolates
    const uint64_t cu = clean.pixels[i] % width / stride, cv = clean.pixels[i] / width / stride;
    for (uint64_t v = cv > 0 ? cv - 1 : 0; v <= cv && v < cells_y; ++v) {
      for (uint64_t u = cu > 0 ? cu - 1 : 0; u <= cu && u < cells_x; ++u) {
        if (cell_wanted[v * cells_x + u]) return true;
      }
    }
    return false;
  };
  // The grid first; with stride 1 every pixel is on it.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    if (cancelled()) return;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (on_grid(i) && grid_needed(i)) out[i] = tracer.Trace(i);
    }
  });
  if (cancelled()) return Cancelled("indirect light: cancelled");
  if (stride == 1) return out;
  std::vector<int32_t> at_pixel(camera.pixel_count(), kNone);
  for (size_t i = 0; i < n; ++i) {
    if (clean.pixels[i] < at_pixel.size()) at_pixel[clean.pixels[i]] = static_cast<int32_t>(i);
  }
  // Bilinear weights of the grid pixels about pixel i; same_surface: only those on its surface.
  const auto interpolate = [&](size_t i, bool same_surface) -> std::optional<IndirectReturn> {
    const uint32_t u = clean.pixels[i] % width, v = clean.pixels[i] / width;
    const uint32_t u0 = u - u % stride, v0 = v - v % stride;
    const double fu = static_cast<double>(u - u0) / stride, fv = static_cast<double>(v - v0) / stride;
    const std::array<uint32_t, 4> us{u0, u0 + stride, u0, u0 + stride}, vs{v0, v0, v0 + stride, v0 + stride};
    const std::array<double, 4> weights{(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
    double total = 0;
    IndirectReturn sum;
    for (size_t k = 0; k < 4; ++k) {
      if (weights[k] <= 0 || us[k] >= width || vs[k] >= camera.height) continue;
      const int32_t g = at_pixel[uint64_t{vs[k]} * width + us[k]];
      if (g == kNone || (same_surface && !SameSurface(clean, i, static_cast<size_t>(g)))) continue;
      total += weights[k];
      sum.radiance += weights[k] * out[g].radiance;
      sum.phasor += weights[k] * out[g].phasor;
    }
    if (!(total > 0)) return std::nullopt;
    return IndirectReturn{sum.radiance / total, sum.phasor / total};
  };
  std::vector<uint8_t> alone(n, 0);  // no grid pixel on its surface: an edge, to be computed itself
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    if (cancelled()) return;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (on_grid(i) || !needed(i)) continue;
      const std::optional<IndirectReturn> value = interpolate(i, true);
      if (value) {
        out[i] = *value;
      } else {
        alone[i] = 1;
      }
    }
  });
  if (cancelled()) return Cancelled("indirect light: cancelled");
  // Within max_samples in all: the first edge pixels (in pixel order, so whatever the threads) are
  // traced, the rest take whatever grid pixels stand about them, so that a scene broken into
  // fragments cannot make the request trace every pixel.
  const uint64_t grid_samples = IndirectGridSamples(camera, spec);
  const uint64_t budget = max_samples > grid_samples ? (max_samples - grid_samples) / spec.indirect_samples : 0;
  std::vector<size_t> traced, rest;
  for (size_t i = 0; i < n; ++i) {
    if (alone[i]) (traced.size() < budget ? traced : rest).push_back(i);
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, traced.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    if (cancelled()) return;
    for (size_t k = r.begin(); k != r.end(); ++k) out[traced[k]] = tracer.Trace(traced[k]);
  });
  for (const size_t i : rest) out[i] = interpolate(i, false).value_or(IndirectReturn{});
  if (cancelled()) return Cancelled("indirect light: cancelled");
  return out;
}

double RangeOfPathLength(const Eigen::Vector3d& emitter, const Eigen::Vector3d& unit_ray, double path_m) {
  return (path_m * path_m - emitter.squaredNorm()) / (2 * (path_m - emitter.dot(unit_ray)));
}

double MultipathRange(const Eigen::Vector3d& emitter, const Eigen::Vector3d& unit_ray, double direct_path_m,
                      double direct_e, std::complex<double> indirect_phasor_e, double modulation_frequency_hz) {
  const std::complex<double> total = direct_e + indirect_phasor_e;
  const double wavenumber = 2 * std::numbers::pi * modulation_frequency_hz / sensor::kSpeedOfLightMs;
  const double excess = std::abs(total) > 0 && wavenumber > 0 ? std::arg(total) / wavenumber : 0.0;
  return RangeOfPathLength(emitter, unit_ray, direct_path_m + excess);
}

}  // namespace vscan::capture
