#pragma once
// Counts every scan the server runs (Scan calls, campaign steps, dataset frames) in the metrics.

#include "raycast/scanner.h"
#include "service/scan/scan_plan.h"
#include "vscan/common/status.h"

namespace vscan::service {

// status: how the scan ended; stats as far as it got; seconds: its wall time.
void RecordScan(ScanBackend backend, const Status& status, const raycast::ScanStats& stats, double seconds);

}  // namespace vscan::service
