#include "vscan/plan/returned_light_plan.h"

#include <cmath>
#include <iterator>
#include <utility>

namespace vscan::plan {

StatusOr<ReturnedLightPlan> ReadReturnedLight(const YamlReader& yaml, const YamlAt& at) {
  // An empty mapping ({}) is every default; ExpectMap refuses anything else that is not a mapping.
  RETURN_IF_ERROR(yaml.ExpectMap(at, kReturnedLightKeys));
  ReturnedLightPlan light;
  double* values[] = {&light.emitter_w_per_sr, &light.emitter_half_angle_deg, &light.exposure_s,
                      &light.aperture_diameter_m, &light.quantum_efficiency, &light.wavelength_m,
                      &light.full_well_e, &light.read_noise_e, &light.min_snr, &light.reference_e,
                      &light.indirect_samples, &light.indirect_stride_px, &light.modulation_frequency_hz,
                      &light.interreflection_ratio, &light.ambient_irradiance_w_per_m2};
  static_assert(std::size(values) == std::size(kReturnedLightKeys));
  for (size_t i = 0; i < std::size(values); ++i) {
    const YamlAt child = YamlReader::Child(at, kReturnedLightKeys[i]);
    if (!YamlReader::Has(child)) continue;
    ASSIGN_OR_RETURN(*values[i], yaml.Number(child));
    if (*values[i] < 0) return yaml.Error(child, "must not be negative (0 takes the default)");
  }
  for (double* count : {&light.indirect_samples, &light.indirect_stride_px}) {
    // Within uint32 and whole: the message's fields are counts.
    if (*count != std::floor(*count) || *count > 4294967295.0) {
      const char* key = count == &light.indirect_samples ? "indirect_samples" : "indirect_stride_px";
      return yaml.Error(YamlReader::Child(at, key), "must be a whole number");
    }
  }
  return light;
}

}  // namespace vscan::plan
