#pragma once
// A ScanRequest's returned_light in engine terms: the emitter placed at the camera or the
// projector, the camera pixel's gain from its exposure, pupil and focal lengths, and the pixel's
// limits. The objects' materials are the scene's, filled in when the scan runs.

#include <optional>

#include "capture/returned_light.h"
#include "sensor/camera.h"
#include "sensor/presets.h"
#include "sensor/structured_light.h"
#include "vscan/common/status.h"
#include "vscan/v1/sensor.pb.h"

namespace vscan::api {

// Every value finite and within the range the message documents; INVALID_ARGUMENT naming
// "returned_light.<field>". sensor_modulation_hz: a time-of-flight preset's modulation frequency,
// taken when the request leaves modulation_frequency_hz 0; preset: a preset's camera and emitter
// figures, taken for the values the request leaves 0 before the generic defaults.
StatusOr<capture::ReturnedLightSpec> ReturnedLightFromProto(const v1::ReturnedLight& light,
                                                           const sensor::PinholeCamera& camera,
                                                           const std::optional<sensor::StructuredLight>& projector,
                                                           double sensor_modulation_hz = 0,
                                                           const sensor::PresetIllumination& preset = {});

}  // namespace vscan::api
