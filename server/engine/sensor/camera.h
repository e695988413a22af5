#pragma once
// Pinhole camera model and the camera-borne light of the paper.

#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::sensor {

// I = power * cos(incidence) / (constant + linear * r + quadratic * r^2).
struct Lighting {
  double power = 1.0;
  double constant = 1.0;
  double linear = 0.0;
  double quadratic = 0.0;
};

// Sensor frame: x right, y down, z forward. near/far bound the depth z, in metres.
struct PinholeCamera {
  uint32_t width = 0;
  uint32_t height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double near = 0.05;
  double far = 10.0;
  Lighting lighting;

  uint64_t pixel_count() const { return uint64_t{width} * height; }
  // Direction through the centre of pixel (u, v) with z = 1, so that t along it is the depth.
  Eigen::Vector3f RayThroughPixel(uint32_t u, uint32_t v) const {
    return {static_cast<float>((u + 0.5 - cx) / fx), static_cast<float>((v + 0.5 - cy) / fy), 1.0f};
  }
};

// Square pixels, principal point at the image centre.
PinholeCamera CameraFromFov(uint32_t width, uint32_t height, double horizontal_fov_deg, double near, double far);

// Checks fx, fy, cx, cy against the physical bounds (physical_limits.h) for the camera's size;
// messages name field.fx and so on.
Status ValidateIntrinsics(const PinholeCamera& camera, std::string_view field);
// Width and height: positive (INVALID_ARGUMENT) and at most 16384 pixels each (RESOURCE_EXHAUSTED).
Status ValidateImageSize(const PinholeCamera& camera, std::string_view field);

// Checks sizes, intrinsics, range and lighting; messages start with field.
Status ValidateCamera(const PinholeCamera& camera, std::string_view field, uint64_t max_rays);

// Intensity of the camera's light at range r on a surface whose normal makes cos_incidence with the ray.
double Intensity(const Lighting& lighting, double range, double cos_incidence);

}  // namespace vscan::sensor
