#pragma once
// The header and statistics messages of a Scan stream.

#include <cstdint>

#include "api/scan/scan_request.h"
#include "capture/measure_scan.h"
#include "raycast/scanner.h"
#include "service/scan/scan_ground_truth.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::api {

// What is known before casting: pose, camera, fields, frame, backend and rays. The point and chunk
// counts are left 0 (unknown until the statistics).
void FillScanHeader(const ScanPlan& plan, uint64_t scene_revision, v1::ScanHeader* header);

// The cast's and the measurement model's figures; the caller adds what was streamed and total_ms.
void ObjectTruthToProto(const service::ObjectTruth& object, v1::ObjectTruth* out);

void FillScanStatistics(const raycast::ScanStats& stats, const capture::MeasureStats& measure,
                        v1::ScanStatistics* out);

}  // namespace vscan::api
