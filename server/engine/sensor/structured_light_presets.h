#pragma once
// Industrial structured-light scanner presets of three working-range classes.

#include <vector>

#include "sensor/presets.h"

namespace vscan::sensor {

// Appends the small, medium and large structured-light presets.
void AppendStructuredLightPresets(std::vector<SensorPreset>& presets);

}  // namespace vscan::sensor
