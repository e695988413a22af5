#pragma once
// What a measured scan asks for on top of the clean one: noise, artefacts, rejection rules,
// ground truth and estimated normals.

#include <cstdint>
#include <optional>
#include <string_view>

#include "capture/returned_light.h"
#include "sensor/measurement.h"
#include "sensor/structured_light.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/status.h"

namespace vscan::capture {

// The paper's outliers: a fraction of the rays is re-cast tilted within a cone and/or from an
// origin moved within a ball.
struct OutlierSpec {
  double rate = 0;       // in [0, 1]
  double angle_deg = 0;  // cone half-angle, [0, 90)
  double origin_m = 0;   // ball radius
  bool any() const { return rate > 0; }
};

// Mixed depths at depth edges.
struct FlyingPixelSpec {
  bool enabled = false;
  double edge_m = 0.02;  // depth jump between 4-neighbours that makes an edge
};

// k-nearest-neighbour normals of the measured cloud (POINT_FIELD_ESTIMATED_NORMAL).
struct NormalEstimationSpec {
  int k = 16;                 // in [3, 128]
  double max_distance = 0;    // metres, 0: no limit
};

struct MeasurementSpec {
  sensor::LensDistortion distortion;
  // Gaussian noise, along the ray or isotropic, and depth quantisation; noise.min_intensity is
  // the REJECTED_DIM threshold.
  sensor::DepthNoise noise;
  OutlierSpec outliers;
  FlyingPixelSpec flying_pixels;
  double grazing_limit_deg = 0;  // 0: off
  NormalEstimationSpec normal_estimation;
  // A structured-light scanner's projector: rays it does not light become REJECTED_UNLIT or
  // REJECTED_SHADOWED, and returned depths are quantised in disparity. Unset: no projector.
  std::optional<sensor::StructuredLight> structured_light;
  // The emitter's light off each object's material: rays too dark or saturated are rejected with that
  // reason, intensity becomes the measured electrons, and the depth noise follows the signal. Unset:
  // intensity is the camera's Lighting and only min_intensity rejects.
  std::optional<ReturnedLightSpec> returned_light;
  bool include_rejected = false;
  // Fields of the returned cloud (kFieldsGroundTruth and kFieldEstimatedNormal included).
  uint32_t fields = kFieldsDefault;
  uint64_t seed = 0;

  // Whether anything here changes the clean scan (false: the clean fast path serves it).
  bool any() const {
    return distortion.any() || noise.any() || outliers.any() || flying_pixels.enabled || grazing_limit_deg > 0 ||
           structured_light.has_value() || returned_light.has_value() || include_rejected || (fields & (kFieldsGroundTruth | kFieldEstimatedNormal)) != 0;
  }
};

// Ranges of the artefact and rejection members; messages name the wire fields under `noise`
// (e.g. "noise.outlier_rate") and "normal_estimation.k".
Status ValidateMeasurementSpec(const MeasurementSpec& spec, std::string_view noise_field,
                               std::string_view normals_field);

}  // namespace vscan::capture
