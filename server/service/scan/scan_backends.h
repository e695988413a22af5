#pragma once
// Runs a validated scan on the backend it names: Embree ray casting or one of the raster methods,
// then the measurement model when the plan asks for any of it.

#include <atomic>

#include "service/context/raster_provider.h"
#include "service/scan/scan_plan.h"
#include "capture/measure_scan.h"
#include "raycast/scanner.h"
#include "scenes/scene_registry.h"

namespace vscan::service {

// stats->points counts the returned measurements (rejected rays returned with include_rejected are
// not among them); measure_stats, when given, gets the measurement model's counters (all zero on
// the clean path).
StatusOr<PointCloud> RunScanBackend(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                                    const std::atomic<bool>* cancel, raycast::ScanStats* stats,
                                    capture::MeasureStats* measure_stats = nullptr);

}  // namespace vscan::service
