#pragma once
// What a planned scan casts against: the scene at the plan's table angle, plus the carrying
// robot's links when its mount makes them visible.

#include "service/scan/scan_plan.h"
#include "service/context/service_context.h"
#include "scenes/scene_registry.h"

namespace vscan::service {

StatusOr<scenes::ScanTarget> PrepareScanTarget(ServiceContext& context, const ScanPlan& plan);

}  // namespace vscan::service
