#include "api/scan_target.h"

namespace vscan::api {

StatusOr<scenes::ScanTarget> PrepareScanTarget(ServiceContext& context, const ScanPlan& plan) {
  return context.registry.PrepareScan(plan.scene_id, plan.table_angle_deg);
}

}  // namespace vscan::api
