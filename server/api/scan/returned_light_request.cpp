#include "api/scan/returned_light_request.h"

#include <numbers>
#include <string>

#include "api/transport/validate.h"
#include "capture/indirect_light.h"

namespace vscan::api {

StatusOr<capture::ReturnedLightSpec> ReturnedLightFromProto(const v1::ReturnedLight& light,
                                                           const sensor::PinholeCamera& camera,
                                                           const std::optional<sensor::StructuredLight>& projector,
                                                           double sensor_modulation_hz,
                                                           const sensor::PresetIllumination& preset) {
  // 0 takes the default; a positive lower bound of 0 is the same as an open one, since 0 is taken.
  const auto read = [](double value, double fallback, double lo, double hi, const char* member, const char* unit) {
    return NumberOrDefault(value, fallback, lo, hi, std::string("returned_light.") + member, unit);
  };
  // The preset's figure where it has one, else the generic default.
  const auto or_generic = [](double preset_value, double generic) { return preset_value > 0 ? preset_value : generic; };
  capture::ReturnedLightSpec spec;
  ASSIGN_OR_RETURN(spec.emitter.radiant_intensity_w_per_sr,
                   read(light.emitter_w_per_sr(), or_generic(preset.emitter_w_per_sr, 1.0), 0, 1e6, "emitter_w_per_sr", "W/sr"));
  ASSIGN_OR_RETURN(const double half_angle_deg,
                   read(light.emitter_half_angle_deg(), 180.0, 0, 180, "emitter_half_angle_deg", "degrees"));
  spec.emitter.cone_half_angle_rad = half_angle_deg * std::numbers::pi / 180.0;
  if (projector) {
    const Pose3 sensor_from_projector = sensor::SensorFromProjector(*projector);
    spec.emitter.position = sensor_from_projector.translation();
    spec.emitter.axis = sensor_from_projector.linear().col(2);
  }
  sensor::PinholePixel pixel;
  ASSIGN_OR_RETURN(pixel.exposure_s, read(light.exposure_s(), or_generic(preset.exposure_s, pixel.exposure_s), 0, 10, "exposure_s", "s"));
  ASSIGN_OR_RETURN(const double pupil_m, read(light.aperture_diameter_m(), or_generic(preset.aperture_diameter_m, 0.004), 0, 1, "aperture_diameter_m", "m"));
  pixel.aperture_area_m2 = std::numbers::pi * pupil_m * pupil_m / 4;
  ASSIGN_OR_RETURN(pixel.quantum_efficiency,
                   read(light.quantum_efficiency(), or_generic(preset.quantum_efficiency, pixel.quantum_efficiency), 0, 1, "quantum_efficiency", ""));
  ASSIGN_OR_RETURN(pixel.wavelength_m, read(light.wavelength_m(), or_generic(preset.wavelength_m, pixel.wavelength_m), 1e-7, 2e-5, "wavelength_m", "m"));
  spec.pixel.gain_e = capture::CameraPixelGain(camera, pixel);
  ASSIGN_OR_RETURN(spec.pixel.full_well_e,
                   read(light.full_well_e(), or_generic(preset.full_well_e, spec.pixel.full_well_e), 0, 1e9, "full_well_e", "electrons"));
  ASSIGN_OR_RETURN(spec.pixel.read_noise_e,
                   read(light.read_noise_e(), or_generic(preset.read_noise_e, spec.pixel.read_noise_e), 0, 1e6, "read_noise_e", "electrons"));
  ASSIGN_OR_RETURN(spec.pixel.min_snr, read(light.min_snr(), spec.pixel.min_snr, 0, 1e3, "min_snr", ""));
  ASSIGN_OR_RETURN(spec.reference_e, read(light.reference_e(), 0.0, 0, 1e9, "reference_e", "electrons"));
  if (light.indirect_samples() > capture::kMaxIndirectSamples) {
    return InvalidArgument("returned_light.indirect_samples",
                           "must be at most " + std::to_string(capture::kMaxIndirectSamples));
  }
  spec.indirect_samples = light.indirect_samples();
  if (light.indirect_stride_px() > capture::kMaxIndirectStridePx) {
    return InvalidArgument("returned_light.indirect_stride_px",
                           "must be in [1, " + std::to_string(capture::kMaxIndirectStridePx) + "] (0: 4)");
  }
  if (light.indirect_stride_px() != 0) spec.indirect_stride_px = light.indirect_stride_px();
  if (capture::IndirectGridSamples(camera, spec) > capture::kMaxIndirectGridSamples) {
    return InvalidArgument("returned_light.indirect_samples",
                           "times the grid's pixels (ceil(width / indirect_stride_px) x ceil(height / "
                           "indirect_stride_px)) must be at most " +
                               std::to_string(capture::kMaxIndirectGridSamples) +
                               ": ask for fewer samples or a wider stride");
  }
  ASSIGN_OR_RETURN(spec.modulation_frequency_hz,
                   read(light.modulation_frequency_hz(), sensor_modulation_hz, 0, capture::kMaxModulationFrequencyHz,
                        "modulation_frequency_hz", "Hz"));
  if (projector && light.modulation_frequency_hz() != 0) {
    return InvalidArgument("returned_light.modulation_frequency_hz",
                           "a structured-light sensor does not measure time of flight; leave it 0");
  }
  ASSIGN_OR_RETURN(spec.interreflection_ratio,
                   read(light.interreflection_ratio(), 1.0, 0, 1e3, "interreflection_ratio", ""));
  ASSIGN_OR_RETURN(spec.ambient_irradiance_w_per_m2,
                   read(light.ambient_irradiance_w_per_m2(), 0.0, 0, capture::kMaxAmbientIrradiance,
                        "ambient_irradiance_w_per_m2", "W/m^2"));
  spec.default_material = sensor::DefaultMaterial();
  RETURN_IF_ERROR(capture::ValidateReturnedLight(spec, "returned_light"));
  return spec;
}

}  // namespace vscan::api
