#include "sensor/pixel_radiometry.h"

#include <cmath>
#include <utility>

namespace vscan::sensor {

Status ValidatePinholePixel(const PinholePixel& pixel, std::string_view field) {
  const std::pair<double, std::string_view> members[] = {{pixel.aperture_area_m2, "aperture_area_m2"},
                                                         {pixel.pixel_solid_angle_sr, "pixel_solid_angle_sr"},
                                                         {pixel.exposure_s, "exposure_s"},
                                                         {pixel.quantum_efficiency, "quantum_efficiency"},
                                                         {pixel.wavelength_m, "wavelength_m"}};
  for (const auto& [value, member] : members) {
    if (!std::isfinite(value)) return InvalidArgument(FieldPath(field, member), "NaN or infinite value");
    if (!(value > 0)) return InvalidArgument(FieldPath(field, member), "must be > 0");
  }
  if (pixel.quantum_efficiency > 1) {
    return InvalidArgument(FieldPath(field, "quantum_efficiency"), "must be at most 1");
  }
  return Status::Ok();
}

double PixelGain(const PinholePixel& pixel) {
  const double photon_energy_j = kPlanckJs * kSpeedOfLightMs / pixel.wavelength_m;
  return pixel.quantum_efficiency * pixel.exposure_s * pixel.aperture_area_m2 * pixel.pixel_solid_angle_sr /
         photon_energy_j;
}

double OffAxisFalloff(const Eigen::Vector3d& ray) {
  const double norm = ray.norm();
  if (!(ray.z() > 0) || !std::isfinite(norm)) return 0;
  const double cos_axis = ray.z() / norm;
  const double cos2 = cos_axis * cos_axis;
  return cos2 * cos2;
}

}  // namespace vscan::sensor
