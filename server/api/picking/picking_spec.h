#pragma once
// A PickingSpec checked into the service's plan: the bin fill job it empties (succeeded, its
// scene and meshes still there), the mount in that scene, the gripper and options, the camera.

#include "service/context/service_context.h"
#include "service/picking/picking_session.h"
#include "store/job_catalogue.h"
#include "vscan/v1/job.pb.h"

namespace vscan::api {

// bin_job is the stored job spec.bin_job_id names (the caller looks it up: NOT_FOUND naming
// "spec.bin_job_id" there). Errors name the spec's fields ("spec.mount_id",
// "spec.gripper.suction.diameter", "spec.width").
StatusOr<service::PickingPlan> ValidatePicking(const v1::PickingSpec& spec, const store::JobRecord& bin_job,
                                               service::ServiceContext& context);

}  // namespace vscan::api
