#include "api/scan/sensor_request.h"

#include <cmath>
#include <string>

#include "api/scan/structured_light_convert.h"
#include "sensor/presets.h"

namespace vscan::api {
namespace {

constexpr double kDefaultNear = 0.05;
constexpr double kDefaultFar = 10.0;

StatusOr<sensor::LensDistortion> DistortionFromProto(const v1::Distortion& d, const std::string& field) {
  sensor::LensDistortion distortion{d.k1(), d.k2(), d.k3(), d.p1(), d.p2()};
  RETURN_IF_ERROR(sensor::ValidateDistortion(distortion, field + ".distortion"));
  return distortion;
}

StatusOr<sensor::PinholeCamera> CameraFromProto(const v1::PinholeCamera& p, const std::string& field,
                                                const service::Limits& limits) {
  const double near = p.near() == 0 ? kDefaultNear : p.near();
  const double far = p.far() == 0 ? kDefaultFar : p.far();
  if (p.width() == 0) return InvalidArgument(FieldPath(field, "width"), "must be positive");
  if (p.height() == 0) return InvalidArgument(FieldPath(field, "height"), "must be positive");
  sensor::PinholeCamera camera;
  switch (p.projection_case()) {
    case v1::PinholeCamera::kIntrinsics: {
      const auto& k = p.intrinsics();
      camera.width = p.width();
      camera.height = p.height();
      camera.fx = k.fx();
      camera.fy = k.fy();
      camera.cx = k.cx();
      camera.cy = k.cy();
      camera.near = near;
      camera.far = far;
      // Checked here so that messages name the wire path (ValidateCamera says "<field>.fx").
      RETURN_IF_ERROR(sensor::ValidateIntrinsics(camera, field + ".intrinsics"));
      break;
    }
    case v1::PinholeCamera::kHorizontalFovDeg: {
      const double fov = p.horizontal_fov_deg();
      if (!std::isfinite(fov) || fov <= 0 || fov >= 180) {
        return InvalidArgument(FieldPath(field, "horizontal_fov_deg"), "must be in (0, 180)");
      }
      camera = sensor::CameraFromFov(p.width(), p.height(), fov, near, far);
      break;
    }
    case v1::PinholeCamera::PROJECTION_NOT_SET:
      return InvalidArgument(field, "intrinsics or horizontal_fov_deg required");
  }
  if (p.has_lighting()) {
    const auto& l = p.lighting();
    camera.lighting = {l.power(), l.constant(), l.linear(), l.quadratic()};
  }
  RETURN_IF_ERROR(sensor::ValidateCamera(camera, field, limits.max_rays_per_scan));
  return camera;
}

}  // namespace

StatusOr<sensor::DepthNoise> NoiseFromProto(const v1::NoiseSpec& n) {
  sensor::DepthNoise noise;
  noise.sigma_a = n.sigma_a();
  noise.sigma_b = n.sigma_b();
  noise.sigma_c = n.sigma_c();
  noise.along_ray = n.along_ray();
  noise.depth_step = n.depth_step_m();
  noise.min_intensity = n.min_intensity();
  RETURN_IF_ERROR(sensor::ValidateNoise(noise, "noise"));
  return noise;
}

StatusOr<SensorSettings> SensorFromProto(const v1::SensorSpec& spec, const service::Limits& limits) {
  SensorSettings settings;
  switch (spec.kind_case()) {
    case v1::SensorSpec::kPinhole: {
      ASSIGN_OR_RETURN(settings.camera, CameraFromProto(spec.pinhole(), "sensor.pinhole", limits));
      ASSIGN_OR_RETURN(settings.distortion, DistortionFromProto(spec.pinhole().distortion(), "sensor.pinhole"));
      return settings;
    }
    case v1::SensorSpec::kStructuredLight: {
      const std::string field = "sensor.structured_light.camera";
      const v1::StructuredLightScanner& sl = spec.structured_light();
      if (!sl.has_camera()) return InvalidArgument(field, "required");
      ASSIGN_OR_RETURN(settings.camera, CameraFromProto(sl.camera(), field, limits));
      ASSIGN_OR_RETURN(settings.distortion, DistortionFromProto(sl.camera().distortion(), field));
      ASSIGN_OR_RETURN(settings.structured_light, StructuredLightFromProto(sl, settings.camera, limits));
      return settings;
    }
    case v1::SensorSpec::kPreset: {
      const sensor::SensorPreset* preset = sensor::FindSensorPreset(spec.preset());
      if (!preset) {
        return NotFound("sensor.preset", "no preset '" + spec.preset() + "' (ListSensorPresets lists them)");
      }
      settings.camera = preset->camera;
      RETURN_IF_ERROR(sensor::ValidateCamera(settings.camera, "sensor.preset", limits.max_rays_per_scan));
      settings.preset_noise = preset->noise;
      settings.structured_light = preset->structured_light;
      settings.modulation_frequency_hz = preset->modulation_frequency_hz;
      settings.illumination = preset->illumination;
      return settings;
    }
    case v1::SensorSpec::KIND_NOT_SET: break;
  }
  return InvalidArgument("sensor", "required (preset, pinhole or structured_light)");
}

}  // namespace vscan::api
