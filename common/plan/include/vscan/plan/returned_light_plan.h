#pragma once
// A plan's returned_light block for readers without protobuf (dataset plans): the keys and meaning
// of the ReturnedLight message (proto/vscan/v1/sensor.proto); 0 takes the message's default. The
// ranges are the server's to check.

#include "vscan/plan/yaml_reader.h"

namespace vscan::plan {

struct ReturnedLightPlan {
  double emitter_w_per_sr = 0;
  double emitter_half_angle_deg = 0;
  double exposure_s = 0;
  double aperture_diameter_m = 0;
  double quantum_efficiency = 0;
  double wavelength_m = 0;
  double full_well_e = 0;
  double read_noise_e = 0;
  double min_snr = 0;
  double reference_e = 0;
  double indirect_samples = 0;    // a whole number
  double indirect_stride_px = 0;  // a whole number
  double modulation_frequency_hz = 0;
  double interreflection_ratio = 0;
  double ambient_irradiance_w_per_m2 = 0;
};

// The message's field names, in its order.
inline constexpr const char* kReturnedLightKeys[] = {
    "emitter_w_per_sr", "emitter_half_angle_deg", "exposure_s",       "aperture_diameter_m",
    "quantum_efficiency", "wavelength_m",         "full_well_e",      "read_noise_e",
    "min_snr",          "reference_e",            "indirect_samples", "indirect_stride_px",
    "modulation_frequency_hz", "interreflection_ratio", "ambient_irradiance_w_per_m2"};

// A mapping of those keys to finite, non-negative numbers (an empty mapping: every default).
StatusOr<ReturnedLightPlan> ReadReturnedLight(const YamlReader& yaml, const YamlAt& at);

}  // namespace vscan::plan
