#pragma once
// A bin fill's picks section (spec.picks) checked when the job starts: the gripper and the options
// by value, the mount in the fill's scene, so that a bad section is refused before any physics.

#include "service/bins/bin_fill_plan.h"
#include "service/context/service_context.h"
#include "service/picking/scene_picks.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

// The section as a pick request (part_object_ids left empty). INVALID_ARGUMENT naming
// "picks.mount_id", "picks.gripper.*", "picks.grasp_options.*" or "picks.pick_options.*".
StatusOr<service::ScenePickRequest> BinPicksFromProto(const v1::BinPicks& picks);

// The section checked and, when it passes, plan.pick_check set to CheckScenePicks over the parts
// it is given. BinPicksFromProto's errors; NOT_FOUND naming "picks.mount_id" when there is no such
// mount; FAILED_PRECONDITION naming it when the mount stands in a scene other than
// plan.request.scene_id (not compared while that is empty); RESOURCE_EXHAUSTED naming
// "picks.grasp_options.candidates" when a part type's grasp search would pass the engine's bound,
// or "picks.pick_options.max_reach_checks" past the picks' bound on inverse kinematics.
Status AddBinPickCheck(const v1::BinPicks& section, service::ServiceContext& context, service::BinFillPlan& plan);

}  // namespace vscan::api
