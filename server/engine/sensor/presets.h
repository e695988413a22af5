#pragma once
// Named sensors with documented sources: a camera model and its measurement noise.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sensor/camera.h"
#include "sensor/measurement.h"
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
};

const std::vector<SensorPreset>& SensorPresets();
// nullptr when no preset has that name.
const SensorPreset* FindSensorPreset(std::string_view name);

}  // namespace vscan::sensor
