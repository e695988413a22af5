#pragma once
// Runs a validated scan on the backend it names: Embree ray casting or one of the raster methods.

#include <atomic>

#include "api/raster_provider.h"
#include "api/scan_request.h"
#include "raycast/scanner.h"
#include "scenes/scene_registry.h"

namespace vscan::api {

StatusOr<PointCloud> RunScanBackend(const ScanPlan& plan, const scenes::ScanTarget& target, RasterProvider& raster,
                                    const std::atomic<bool>* cancel, raycast::ScanStats* stats);

}  // namespace vscan::api
