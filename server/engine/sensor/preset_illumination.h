#pragma once
// A sensor preset's camera and emitter figures for the returned light (docs/SENSORS.md, "Presets").

#include <string>

#include "sensor/camera.h"

namespace vscan::sensor {

// What a preset's scans with returned light take for each value the request leaves 0 (0 here: the
// generic default of sensor.proto), and where the figures come from.
struct PresetIllumination {
  double emitter_w_per_sr = 0;
  double exposure_s = 0;
  double aperture_diameter_m = 0;
  double quantum_efficiency = 0;
  double wavelength_m = 0;
  double full_well_e = 0;
  double read_noise_e = 0;
  std::string source;
};

// The radiant intensity that puts half the full well on a white (albedo 0.9) Lambertian surface
// facing the camera on its axis at distance_m, lit from the camera: the design point that stands in
// for an emitter whose power its maker does not publish (an exposure set for mid-scale on white).
double HalfWellEmitter(const PinholeCamera& camera, const PresetIllumination& light, double distance_m);

}  // namespace vscan::sensor
