#include "sensor/preset_illumination.h"

#include <numbers>

#include "sensor/pixel_radiometry.h"

namespace vscan::sensor {

double HalfWellEmitter(const PinholeCamera& camera, const PresetIllumination& light, double distance_m) {
  PinholePixel pixel;
  pixel.aperture_area_m2 = std::numbers::pi * light.aperture_diameter_m * light.aperture_diameter_m / 4;
  pixel.pixel_solid_angle_sr = 1.0 / (camera.fx * camera.fy);
  pixel.exposure_s = light.exposure_s;
  pixel.quantum_efficiency = light.quantum_efficiency;
  pixel.wavelength_m = light.wavelength_m;
  constexpr double kWhiteAlbedo = 0.9;
  // Electrons = gain x (albedo / pi) x I / d^2 on the axis, facing.
  return 0.5 * light.full_well_e * distance_m * distance_m / (PixelGain(pixel) * kWhiteAlbedo / std::numbers::pi);
}

}  // namespace vscan::sensor
