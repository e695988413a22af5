#pragma once
// PickingService requests into the service's types: unset fields take their defaults, the rest is
// validated where it is used (the gripper, the options) and named by its request field.

#include "grasping/grasp_generation.h"
#include "grasping/gripper.h"
#include "service/picking/scene_picks.h"
#include "vscan/common/status.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::api {

// INVALID_ARGUMENT "gripper" when neither kind is set; zero fields take the defaults.
StatusOr<grasping::Gripper> ParseGripper(const v1::Gripper& gripper);
grasping::GraspOptions ParseGraspOptions(const v1::GraspOptions& options);
// INVALID_ARGUMENT naming "mount_id" or "part_object_ids[i]" for an id no record can have.
StatusOr<service::ScenePickRequest> ParseCheckPicksRequest(const v1::CheckPicksRequest& request);

// An error of the engine or the service (which name their own fields, "gripper.suction.diameter_m",
// "body_length_m") naming the request's field instead ("gripper.suction.diameter",
// "pick_options.body_length"); other errors pass unchanged.
Status InRequestTerms(const Status& status);

}  // namespace vscan::api
