#pragma once
// Named sensors with documented sources: a camera model and its measurement noise.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sensor/camera.h"
#include "sensor/measurement.h"
#include "sensor/preset_illumination.h"
#include "sensor/structured_light.h"

namespace vscan::sensor {

struct SensorPreset {
  std::string name;
  std::string description;
  // Where the numbers come from.
  std::string source;
  PinholeCamera camera;
  DepthNoise noise;
  // Set for structured-light scanners; its camera is the same as `camera`.
  std::optional<StructuredLight> structured_light;
  // Set (Hz) for time-of-flight cameras: the modulation frequency whose phase gives the depth when
  // the returned light has indirect light (multipath); 0: not time of flight.
  double modulation_frequency_hz = 0;
  PresetIllumination illumination;
};

// A time-of-flight preset's modulation frequency: one frequency standing for the several a real
// camera combines to unwrap its phase.
inline constexpr double kDefaultModulationFrequencyHz = 20e6;

const std::vector<SensorPreset>& SensorPresets();
// nullptr when no preset has that name.
const SensorPreset* FindSensorPreset(std::string_view name);

}  // namespace vscan::sensor
