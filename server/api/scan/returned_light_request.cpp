#include "api/scan/returned_light_request.h"

#include <cmath>
#include <numbers>
#include <string>

namespace vscan::api {
namespace {

// value, or fallback for 0; INVALID_ARGUMENT unless finite and within [lo, hi] (above lo when
// lo_open).
StatusOr<double> Within(double value, double fallback, double lo, double hi, bool lo_open, const char* field,
                        const char* unit) {
  if (value == 0) return fallback;
  if (!std::isfinite(value) || value < lo || value > hi || (lo_open && value == lo)) {
    return InvalidArgument(std::string("returned_light.") + field,
                           "must be within " + std::string(lo_open ? "(" : "[") + std::to_string(lo) + ", " +
                               std::to_string(hi) + "] " + unit + " (0: the default)");
  }
  return value;
}

}  // namespace

StatusOr<capture::ReturnedLightSpec> ReturnedLightFromProto(const v1::ReturnedLight& light,
                                                           const sensor::PinholeCamera& camera,
                                                           const std::optional<sensor::StructuredLight>& projector) {
  capture::ReturnedLightSpec spec;
  ASSIGN_OR_RETURN(spec.emitter.radiant_intensity_w_per_sr,
                   Within(light.emitter_w_per_sr(), 1.0, 0, 1e6, false, "emitter_w_per_sr", "W/sr"));
  ASSIGN_OR_RETURN(const double half_angle_deg,
                   Within(light.emitter_half_angle_deg(), 180.0, 0, 180, true, "emitter_half_angle_deg", "degrees"));
  spec.emitter.cone_half_angle_rad = half_angle_deg * std::numbers::pi / 180.0;
  if (projector) {
    const Pose3 sensor_from_projector = sensor::SensorFromProjector(*projector);
    spec.emitter.position = sensor_from_projector.translation();
    spec.emitter.axis = sensor_from_projector.linear().col(2);
  }
  sensor::PinholePixel pixel;
  ASSIGN_OR_RETURN(pixel.exposure_s, Within(light.exposure_s(), pixel.exposure_s, 0, 10, true, "exposure_s", "s"));
  ASSIGN_OR_RETURN(const double pupil_m,
                   Within(light.aperture_diameter_m(), 0.004, 0, 1, true, "aperture_diameter_m", "m"));
  pixel.aperture_area_m2 = std::numbers::pi * pupil_m * pupil_m / 4;
  ASSIGN_OR_RETURN(pixel.quantum_efficiency,
                   Within(light.quantum_efficiency(), pixel.quantum_efficiency, 0, 1, true, "quantum_efficiency", ""));
  ASSIGN_OR_RETURN(pixel.wavelength_m,
                   Within(light.wavelength_m(), pixel.wavelength_m, 1e-7, 2e-5, false, "wavelength_m", "m"));
  spec.pixel.gain_e = capture::CameraPixelGain(camera, pixel);
  ASSIGN_OR_RETURN(spec.pixel.full_well_e,
                   Within(light.full_well_e(), spec.pixel.full_well_e, 0, 1e9, true, "full_well_e", "electrons"));
  ASSIGN_OR_RETURN(spec.pixel.read_noise_e,
                   Within(light.read_noise_e(), spec.pixel.read_noise_e, 0, 1e6, false, "read_noise_e", "electrons"));
  ASSIGN_OR_RETURN(spec.pixel.min_snr, Within(light.min_snr(), spec.pixel.min_snr, 0, 1e3, false, "min_snr", ""));
  ASSIGN_OR_RETURN(spec.reference_e,
                   Within(light.reference_e(), 0.0, 0, 1e9, false, "reference_e", "electrons"));
  spec.default_material = sensor::DefaultMaterial();
  RETURN_IF_ERROR(capture::ValidateReturnedLight(spec, "returned_light"));
  return spec;
}

}  // namespace vscan::api
