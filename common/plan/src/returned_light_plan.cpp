#include "vscan/plan/returned_light_plan.h"

#include <utility>

namespace vscan::plan {

StatusOr<ReturnedLightPlan> ReadReturnedLight(const YamlReader& yaml, const YamlAt& at) {
  // An empty mapping ({}) is every default; ExpectMap refuses anything else that is not a mapping.
  RETURN_IF_ERROR(yaml.ExpectMap(at, {"emitter_w_per_sr", "emitter_half_angle_deg", "exposure_s",
                                      "aperture_diameter_m", "quantum_efficiency", "wavelength_m", "full_well_e",
                                      "read_noise_e", "min_snr", "reference_e"}));
  ReturnedLightPlan light;
  double* values[] = {&light.emitter_w_per_sr, &light.emitter_half_angle_deg, &light.exposure_s,
                      &light.aperture_diameter_m, &light.quantum_efficiency, &light.wavelength_m,
                      &light.full_well_e, &light.read_noise_e, &light.min_snr, &light.reference_e};
  for (size_t i = 0; i < std::size(values); ++i) {
    const YamlAt child = YamlReader::Child(at, kReturnedLightKeys[i]);
    if (!YamlReader::Has(child)) continue;
    ASSIGN_OR_RETURN(*values[i], yaml.Number(child));
    if (*values[i] < 0) return yaml.Error(child, "must not be negative (0 takes the default)");
  }
  return light;
}

}  // namespace vscan::plan
