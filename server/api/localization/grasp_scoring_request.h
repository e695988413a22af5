#pragma once
// The gripper, grasp options and up direction of ScorePosesRequest and ScoreDatasetResultsRequest.

#include <optional>

#include "service/localization/grasp_scoring.h"
#include "vscan/common/status.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::api {

// Unset when has_gripper is false (the other fields are then ignored). INVALID_ARGUMENT naming
// "gripper.*", "grasp_options.*" or "up".
StatusOr<std::optional<service::GraspScoring>> ParseGraspScoring(bool has_gripper, const v1::Gripper& gripper,
                                                                 const v1::GraspOptions& options, bool has_up,
                                                                 const v1::Vector3& up);

}  // namespace vscan::api
