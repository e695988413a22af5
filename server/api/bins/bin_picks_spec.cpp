#include "api/bins/bin_picks_spec.h"

#include <string>
#include <variant>

#include "api/picking/pick_request.h"
#include "api/transport/validate.h"

namespace vscan::api {

StatusOr<service::ScenePickRequest> BinPicksFromProto(const v1::BinPicks& picks) {
  RETURN_IF_ERROR(RequireId(picks.mount_id(), "picks.mount_id"));
  v1::CheckPicksRequest as_call;
  as_call.set_mount_id(picks.mount_id());
  *as_call.mutable_gripper() = picks.gripper();
  *as_call.mutable_grasp_options() = picks.grasp_options();
  *as_call.mutable_pick_options() = picks.pick_options();
  auto request = ParseCheckPicksRequest(as_call);
  if (!request.ok()) return request.status().WithFieldPrefix("picks");
  if (Status checked = service::CheckPickSettings(*request); !checked.ok()) {
    return InRequestTerms(checked).WithFieldPrefix("picks");
  }
  return request;
}

Status AddBinPickCheck(const v1::BinPicks& section, service::ServiceContext& context, service::BinFillPlan& plan) {
  ASSIGN_OR_RETURN(service::ScenePickRequest picks, BinPicksFromProto(section));
  const auto mounted = context.robots.Mount(picks.mount_id);
  if (!mounted.ok()) {
    if (mounted.status().code() == StatusCode::kNotFound) {
      return NotFound("picks.mount_id", "no mount '" + picks.mount_id + "'");
    }
    return mounted.status();
  }
  const std::string& scene_id = plan.request.scene_id;
  if (!scene_id.empty() && mounted->mount.scene_id != scene_id) {
    return FailedPrecondition("picks.mount_id", "mount '" + picks.mount_id + "' stands in scene '" +
                                                    mounted->mount.scene_id + "', not in the fill's scene '" +
                                                    scene_id + "'");
  }
  for (const physics::PartType& part : plan.parts) {
    if (Status work = grasping::CheckGraspWork(part.mesh.triangles.size(), picks.gripper, picks.grasp_options);
        !work.ok()) {
      return work.WithFieldPrefix("picks");
    }
  }
  if (Status work = service::CheckReachWork(picks, plan.parts_total()); !work.ok()) return work.WithFieldPrefix("picks");
  const std::string gripper = std::holds_alternative<grasping::SuctionCup>(picks.gripper) ? "suction" : "jaws";
  plan.pick_check = [&context, picks, gripper](const std::vector<std::string>& part_object_ids,
                                               const std::atomic<bool>* cancel) -> StatusOr<service::BinPicks> {
    service::BinPicks out;
    out.mount_id = picks.mount_id;
    out.gripper = gripper;
    // No part placed: nothing to check (an empty list would mean every bin part of the scene).
    if (part_object_ids.empty()) return out;
    service::ScenePickRequest request = picks;
    request.part_object_ids = part_object_ids;
    ASSIGN_OR_RETURN(service::ScenePicks checked, service::CheckScenePicks(context, request, cancel));
    for (service::ObjectPick& part : checked.parts) {
      out.parts.push_back({part.object_id, std::move(part.verdict), part.covered_by_object_id});
    }
    out.grasps_generated = checked.grasps_generated;
    out.elapsed_s = checked.elapsed_s;
    return out;
  };
  return Status::Ok();
}

}  // namespace vscan::api
