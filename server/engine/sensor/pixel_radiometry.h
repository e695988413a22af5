#pragma once
// What one pinhole-camera pixel makes of the radiance in front of it: the physical numbers (aperture,
// pixel solid angle, exposure, quantum efficiency, wavelength) folded into the single gain that
// PixelResponse::gain_e carries, and the cos^4 fall-off away from the optical axis
// (docs/SENSORS.md, "The returned signal").

#include <string_view>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::sensor {

inline constexpr double kPlanckJs = 6.62607015e-34;     // h, exact in the SI
inline constexpr double kSpeedOfLightMs = 299792458.0;  // c, exact in the SI

struct PinholePixel {
  double aperture_area_m2 = 1.2566e-5;   // the entrance pupil: pi (f / (2 N))^2, here f = 8 mm at f/2
  double pixel_solid_angle_sr = 1.4e-7;  // on the optical axis: pixel area / f^2, here 3 um at 8 mm
  double exposure_s = 0.01;
  double quantum_efficiency = 0.3;       // electrons per photon at the wavelength
  double wavelength_m = 850e-9;
};

// Every member finite and positive, quantum_efficiency at most 1; INVALID_ARGUMENT naming
// "<field>.<member>".
Status ValidatePinholePixel(const PinholePixel& pixel, std::string_view field);

// Electrons per unit of radiance (W / (m^2 sr)) for a pixel on the optical axis:
// QE t A Omega lambda / (h c), the photons of the power L A Omega over one exposure.
double PixelGain(const PinholePixel& pixel);

// cos^4 of the angle between a ray through a pixel (any length, sensor frame, z forward) and the
// optical axis: an oblique pixel sees the aperture foreshortened (cos) and spans a smaller solid
// angle (cos^3: its area turns away by cos and lies 1 / cos farther). 0 for a ray not ahead.
double OffAxisFalloff(const Eigen::Vector3d& ray);

}  // namespace vscan::sensor
