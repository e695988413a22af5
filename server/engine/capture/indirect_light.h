#pragma once
// One-bounce indirect light of the sensor's own emitter: light that reaches a pixel's surface point
// x1 from a second surface x2 that the emitter lights (docs/SENSORS.md, "Indirect light"). It adds
// to the pixel's signal, biases a time-of-flight depth (multipath) and can drown a structured-light
// pattern (interreflection).

#include <atomic>
#include <complex>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "capture/returned_light.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::capture {

// What one request may ask for: about two minutes of bounces on 2 cores.
inline constexpr uint64_t kMaxIndirectGridSamples = uint64_t{1} << 27;

struct IndirectReturn {
  // The one-bounce radiance x1 sends to the camera, W / (m^2 sr).
  double radiance = 0;
  // The same light as a phasor at the modulation frequency, relative to the direct path:
  // sum of radiance_k exp(i 2 pi f (L_k - L_direct) / c), L the path emitter -> ... -> camera.
  std::complex<double> phasor{0, 0};
};

// One IndirectReturn per point of clean (sensor frame, with normals, instance ids and pixels; scene
// in the world, world_from_sensor placing the sensor in it). For each computed pixel,
// spec.indirect_samples cosine-weighted directions about x1's normal, each drawn from
// (seed, pixel, sample), are cast to x2; x2 is lit by spec.emitter (its cone, and a shadow ray from
// the emitter) and sends x1 DirectRadiance with its material, which x1's BRDF turns to the camera.
// Pixels on the grid of spec.indirect_stride_px are computed; the others interpolate the grid
// pixels around them that lie on the same surface (same object, normals within 26 degrees, within
// 1% of the range of its plane), or are computed themselves when none does. wanted, when not
// empty, marks the points whose value is needed: others come back zero, except grid pixels that a
// wanted pixel may interpolate from.
// Deterministic for a seed, whatever the number of threads. All zero when indirect_samples is 0.
// cancel, when set, is polled between blocks of pixels and stops the work with CANCELLED.
// max_samples bounds the samples traced in all: once the grid's and the first edge pixels' reach it,
// the remaining edge pixels interpolate whatever grid pixels stand about them, on any surface.
StatusOr<std::vector<IndirectReturn>> IndirectReturns(const raycast::RaycastScene& scene,
                                                      const Pose3& world_from_sensor,
                                                      const sensor::PinholeCamera& camera, const PointCloud& clean,
                                                      const ReturnedLightSpec& spec, uint64_t seed,
                                                      const std::vector<uint8_t>& wanted = {},
                                                      const std::atomic<bool>* cancel = nullptr,
                                                      uint64_t max_samples = 2 * kMaxIndirectGridSamples);

// The samples a scan of this camera traces on its grid: indirect_samples x the grid pixels
// (ceil(width / stride) x ceil(height / stride)); the pixels traced off the grid add to it.
uint64_t IndirectGridSamples(const sensor::PinholeCamera& camera, const ReturnedLightSpec& spec);

// The range along the unit ray from the camera (at the origin) at which the path
// emitter -> point -> camera is path_m long: r = (L^2 - |e|^2) / (2 (L - e.u)).
double RangeOfPathLength(const Eigen::Vector3d& emitter, const Eigen::Vector3d& unit_ray, double path_m);

// Time of flight: the range a pixel measures from the phase of the sum of its direct light
// (direct_e electrons, path length direct_path_m) and its indirect light (indirect_phasor_e, in
// electrons, relative to the direct path), at modulation_frequency_hz. The phase difference is
// taken in (-pi, pi], so the bias stays within half the ambiguity interval c / (2 f).
double MultipathRange(const Eigen::Vector3d& emitter, const Eigen::Vector3d& unit_ray, double direct_path_m,
                      double direct_e, std::complex<double> indirect_phasor_e, double modulation_frequency_hz);

}  // namespace vscan::capture
