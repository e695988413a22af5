#include "sensor/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "vscan/common/physical_limits.h"

namespace vscan::sensor {
namespace {

constexpr uint32_t kMaxSide = 16384;
constexpr double kMinLightingTerm = 1e-6;
constexpr double kMaxLightingTerm = 1e6;

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
  // Intensities are single precision: bounded terms keep power / attenuation finite at any range.
  const auto in_range = [](double term) { return term == 0 || (term >= kMinLightingTerm && term <= kMaxLightingTerm); };
  if (l.power > kMaxLightingTerm || !in_range(l.constant) || !in_range(l.linear) || !in_range(l.quadratic)) {
    return InvalidArgument(path + ": power at most 1e6; each attenuation term 0 or in [1e-6, 1e6]");
  }
  return Status::Ok();
}

// One image axis: focal length f and principal point c over `pixels`. Bounds the tangent of the
// widest ray so that ray directions stay finite and far inside float range.
Status ValidateAxis(double f, double c, uint32_t pixels, std::string_view field, const char* f_name,
                    const char* c_name) {
  if (!std::isfinite(f) || f < kMinFocalPx || f > kMaxFocalPx) {
    return InvalidArgument(FieldPath(field, f_name) + ": must be between 0.01 and 1e8 pixels");
  }
  if (!std::isfinite(c) || std::abs(c - pixels / 2.0) > 10.0 * pixels) {
    return InvalidArgument(FieldPath(field, c_name) + ": must be finite and within 10 image sizes of the centre");
  }
  const double widest = std::max(std::abs(0.5 - c), std::abs(pixels - 0.5 - c));
  if (widest / f > kMaxRayTangent) {
    return InvalidArgument(FieldPath(field, f_name) + ": field of view reaches 90 degrees off axis (" +
                           FieldPath(field, c_name) + " / " + f_name + " gives a ray tangent above 1000)");
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

Status ValidateIntrinsics(const PinholeCamera& camera, std::string_view field) {
  RETURN_IF_ERROR(ValidateAxis(camera.fx, camera.cx, camera.width, field, "fx", "cx"));
  return ValidateAxis(camera.fy, camera.cy, camera.height, field, "fy", "cy");
}

Status ValidateImageSize(const PinholeCamera& camera, std::string_view field) {
  if (camera.width == 0) return InvalidArgument(FieldPath(field, "width"), "must be positive");
  if (camera.height == 0) return InvalidArgument(FieldPath(field, "height"), "must be positive");
  if (camera.width > kMaxSide) {
    return ResourceExhausted(FieldPath(field, "width"), "at most " + std::to_string(kMaxSide) + " pixels");
  }
  if (camera.height > kMaxSide) {
    return ResourceExhausted(FieldPath(field, "height"), "at most " + std::to_string(kMaxSide) + " pixels");
  }
  return Status::Ok();
}

Status ValidateCamera(const PinholeCamera& camera, std::string_view field, uint64_t max_rays) {
  RETURN_IF_ERROR(ValidateImageSize(camera, field));
  if (camera.pixel_count() > max_rays) {
    return ResourceExhausted(FieldPath(field, "width") + " x " + FieldPath(field, "height") + ": " +
                             std::to_string(camera.pixel_count()) + " rays exceed the limit of " +
                             std::to_string(max_rays));
  }
  RETURN_IF_ERROR(ValidateIntrinsics(camera, field));
  if (!std::isfinite(camera.near) || camera.near < kMinNearM) {
    return InvalidArgument(FieldPath(field, "near") + ": must be at least 1e-6 m");
  }
  if (!std::isfinite(camera.far) || camera.far > kMaxFarM) {
    return InvalidArgument(FieldPath(field, "far") + ": must be finite and at most 1e5 m");
  }
  if (camera.near >= camera.far) return InvalidArgument(FieldPath(field, "near") + " must be less than far");
  return ValidateLighting(camera.lighting, field);
}

double Intensity(const Lighting& lighting, double range, double cos_incidence) {
  const double attenuation = lighting.constant + lighting.linear * range + lighting.quadratic * range * range;
  return lighting.power * std::max(cos_incidence, 0.0) / attenuation;
}

}  // namespace vscan::sensor
