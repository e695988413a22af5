#include "sensor/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace vscan::sensor {
namespace {

constexpr uint32_t kMaxSide = 16384;

bool FinitePositive(double x) { return std::isfinite(x) && x > 0; }

Status ValidateLighting(const Lighting& l, std::string_view field) {
  const std::string path = FieldPath(field, "lighting");
  if (!std::isfinite(l.power) || !std::isfinite(l.constant) || !std::isfinite(l.linear) ||
      !std::isfinite(l.quadratic)) {
    return InvalidArgument(path, "NaN or infinite value");
  }
  if (l.power < 0 || l.constant < 0 || l.linear < 0 || l.quadratic < 0) {
    return InvalidArgument(path, "power and attenuation terms must be non-negative");
  }
  if (l.constant + l.linear + l.quadratic <= 0) {
    return InvalidArgument(path, "constant + linear + quadratic attenuation must be positive");
  }
  return Status::Ok();
}

}  // namespace

PinholeCamera CameraFromFov(uint32_t width, uint32_t height, double horizontal_fov_deg, double near, double far) {
  PinholeCamera camera;
  camera.width = width;
  camera.height = height;
  const double half_fov = horizontal_fov_deg * std::numbers::pi / 360.0;
  camera.fx = camera.fy = (width / 2.0) / std::tan(half_fov);
  camera.cx = width / 2.0;
  camera.cy = height / 2.0;
  camera.near = near;
  camera.far = far;
  return camera;
}

Status ValidateCamera(const PinholeCamera& camera, std::string_view field, uint64_t max_rays) {
  if (camera.width == 0) return InvalidArgument(FieldPath(field, "width"), "must be positive");
  if (camera.height == 0) return InvalidArgument(FieldPath(field, "height"), "must be positive");
  if (camera.width > kMaxSide) {
    return ResourceExhausted(FieldPath(field, "width"), "at most " + std::to_string(kMaxSide) + " pixels");
  }
  if (camera.height > kMaxSide) {
    return ResourceExhausted(FieldPath(field, "height"), "at most " + std::to_string(kMaxSide) + " pixels");
  }
  if (camera.pixel_count() > max_rays) {
    return ResourceExhausted(FieldPath(field, "width") + " x " + FieldPath(field, "height") + ": " +
                             std::to_string(camera.pixel_count()) + " rays exceed the limit of " +
                             std::to_string(max_rays));
  }
  if (!FinitePositive(camera.fx)) return InvalidArgument(FieldPath(field, "fx"), "must be finite and positive");
  if (!FinitePositive(camera.fy)) return InvalidArgument(FieldPath(field, "fy"), "must be finite and positive");
  if (!std::isfinite(camera.cx)) return InvalidArgument(FieldPath(field, "cx"), "must be finite");
  if (!std::isfinite(camera.cy)) return InvalidArgument(FieldPath(field, "cy"), "must be finite");
  if (!FinitePositive(camera.near)) return InvalidArgument(FieldPath(field, "near"), "must be finite and positive");
  if (!std::isfinite(camera.far)) return InvalidArgument(FieldPath(field, "far"), "must be finite");
  if (camera.near >= camera.far) return InvalidArgument(FieldPath(field, "near") + " must be less than far");
  return ValidateLighting(camera.lighting, field);
}

double Intensity(const Lighting& lighting, double range, double cos_incidence) {
  const double attenuation = lighting.constant + lighting.linear * range + lighting.quadratic * range * range;
  return lighting.power * std::max(cos_incidence, 0.0) / attenuation;
}

}  // namespace vscan::sensor
