#pragma once
// The sensor and noise parts of a request (ScanRequest, CampaignSpec) in engine terms. Error
// messages name the fields relative to the request ("sensor.pinhole.width", "noise.sigma_a").

#include <optional>

#include "service/context/server_options.h"
#include "sensor/camera.h"
#include "sensor/measurement.h"
#include "sensor/presets.h"
#include "sensor/structured_light.h"
#include "vscan/common/status.h"
#include "vscan/v1/sensor.pb.h"

namespace vscan::api {

struct SensorSettings {
  sensor::PinholeCamera camera;
  sensor::LensDistortion distortion;
  // A preset's own noise, used when the request sets none.
  std::optional<sensor::DepthNoise> preset_noise;
  // Set for structured-light scanners; camera is then its camera.
  std::optional<sensor::StructuredLight> structured_light;
  // A time-of-flight preset's modulation frequency (Hz); 0: not time of flight.
  double modulation_frequency_hz = 0;
  // A preset's camera and emitter figures for the returned light.
  sensor::PresetIllumination illumination;
};

StatusOr<SensorSettings> SensorFromProto(const v1::SensorSpec& spec, const service::Limits& limits);
// The depth members of the noise (sigma, quantisation, dim threshold); the artefact members
// (outliers, grazing, flying pixels) are read by MeasurementFromProto.
StatusOr<sensor::DepthNoise> NoiseFromProto(const v1::NoiseSpec& n);

}  // namespace vscan::api
