#pragma once
// A validated ScanRequest in engine terms.

#include "service/scan/scan_plan.h"
#include "service/context/server_options.h"
#include "robot_registry/robot_registry.h"
#include "vscan/v1/scan.pb.h"

namespace vscan::api {

using service::ScanBackend;
using service::ScanPlan;

// The request's backend and frame enums (errors name "backend" and "frame").
StatusOr<ScanBackend> BackendFromProto(int backend);
StatusOr<raycast::ScanFrame> FrameFromProto(int frame);

// Checks every field of the request; the first problem found is returned, naming its field.
// Robot placements are resolved through robots.
StatusOr<ScanPlan> ParseScanRequest(const v1::ScanRequest& request, const service::Limits& limits,
                                    robot_registry::RobotRegistry& robots);

}  // namespace vscan::api
