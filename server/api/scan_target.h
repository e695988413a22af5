#pragma once
// What a planned scan casts against: the scene at the plan's table angle, plus the carrying
// robot's links when its mount makes them visible.

#include "api/scan_request.h"
#include "api/service_context.h"
#include "scenes/scene_registry.h"

namespace vscan::api {

StatusOr<scenes::ScanTarget> PrepareScanTarget(ServiceContext& context, const ScanPlan& plan);

}  // namespace vscan::api
