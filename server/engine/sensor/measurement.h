#pragma once
// Measurement model applied to a clean scan in the sensor frame: lens distortion, depth noise,
// depth quantisation and intensity drop-out.

#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::sensor {

// Brown-Conrady coefficients on normalised image coordinates (x/z, y/z).
struct LensDistortion {
  double k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0;
  bool any() const { return k1 != 0 || k2 != 0 || k3 != 0 || p1 != 0 || p2 != 0; }
};

// Gaussian sigma(z) = sigma_a + sigma_b z + sigma_c z^2 in metres; depth_step in metres (0: off);
// points dimmer than min_intensity are dropped (0: off).
struct DepthNoise {
  double sigma_a = 0, sigma_b = 0, sigma_c = 0;
  bool along_ray = false;
  double depth_step = 0;
  double min_intensity = 0;
  bool any() const { return sigma_a != 0 || sigma_b != 0 || sigma_c != 0 || depth_step != 0 || min_intensity != 0; }
};

// Coefficients must be finite; messages start with field, e.g. "sensor.pinhole.distortion.k1".
Status ValidateDistortion(const LensDistortion& distortion, std::string_view field);
// Sigmas, step and min_intensity must be finite and non-negative; members use the wire names
// (sigma_a, sigma_b, sigma_c, depth_step_m, min_intensity).
Status ValidateNoise(const DepthNoise& noise, std::string_view field);

// Distortion, then noise, then depth quantisation of one sensor-frame point, whose noise draws
// come from (seed, key) only. False when the quantised depth is not positive or the point is no
// longer finite in single precision (the point is dropped).
// min_intensity is not looked at here.
bool MeasurePoint(Eigen::Vector3d& p, const LensDistortion& distortion, const DepthNoise& noise, uint64_t seed,
                  uint64_t key);

// Applies distortion, then noise (isotropic or along the ray), then depth quantisation, then drop-out,
// to a cloud in the sensor frame (z forward). Ranges of moved points are recomputed; normals are left as they are.
// Points at or behind the sensor plane are not distorted, and points whose quantised depth is not positive
// (or that leave single precision) are dropped. Each point's noise comes from (seed, pixel index) when the cloud has pixels, else (seed, point index),
// so the result is reproducible bit for bit.
Status ApplyMeasurementModel(PointCloud& sensor_frame_cloud, const LensDistortion& distortion,
                             const DepthNoise& noise, uint64_t seed);

}  // namespace vscan::sensor
