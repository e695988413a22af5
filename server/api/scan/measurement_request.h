#pragma once
// The measurement-model parts of a ScanRequest (noise artefacts, include_rejected,
// normal_estimation) in engine terms.

#include "capture/measurement_spec.h"
#include "vscan/common/status.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::api {

// Outliers, grazing limit, flying pixels, rejected rays and normal estimation, checked against
// fields (the request's PointFields bits), which the spec keeps. Distortion, depth noise and seed
// are left at their defaults: ParseScanRequest fills them from the sensor and the noise.
StatusOr<capture::MeasurementSpec> MeasurementFromProto(const v1::ScanRequest& request, uint32_t fields);

}  // namespace vscan::api
