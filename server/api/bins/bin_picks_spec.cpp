#include "api/bins/bin_picks_spec.h"

#include <cmath>
#include <string>
#include <variant>

#include "api/picking/pick_request.h"
#include "api/transport/validate.h"

namespace vscan::api {
namespace {

// The engine refuses a grasp search past this much work (docs/GRASPING.md).
constexpr double kMaxGraspWork = 2e9;

Status InRange(double value, double lo, double hi, const std::string& field, const std::string& unit) {
  if (!std::isfinite(value) || value < lo || value > hi) {
    return InvalidArgument(field, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] " + unit +
                                      " (0: the default)");
  }
  return Status::Ok();
}

Status CheckGraspOptions(const grasping::GraspOptions& o) {
  RETURN_IF_ERROR(InRange(double(o.max_grasps), 1, 100000, "grasp_options.max_grasps", "grasps"));
  RETURN_IF_ERROR(InRange(double(o.candidates), 1, 100000, "grasp_options.candidates", "points"));
  RETURN_IF_ERROR(InRange(double(o.surface_samples), 100, 2000000, "grasp_options.surface_samples", "samples"));
  return Status::Ok();
}

Status CheckPickOptions(const service::ScenePickRequest& request) {
  const grasping::PickOptions& o = request.pick_options;
  RETURN_IF_ERROR(InRange(o.sweep.approach_m, 0, 10, "pick_options.approach_distance", "m"));
  RETURN_IF_ERROR(InRange(o.max_approach_tilt_deg, 0, 180, "pick_options.max_approach_tilt_deg", "degrees"));
  RETURN_IF_ERROR(InRange(o.cover_distance_m, 0, 1, "pick_options.cover_distance", "m"));
  RETURN_IF_ERROR(InRange(double(o.max_reach_checks), 1, 1000, "pick_options.max_reach_checks", "grasps"));
  RETURN_IF_ERROR(InRange(request.body_length_m, 0, 10, "pick_options.body_length", "m"));
  const double budget_ms = std::chrono::duration<double, std::milli>(request.ik_time_budget).count();
  return InRange(budget_ms, 1, 1000, "pick_options.ik_time_budget_ms", "ms");
}

// The engine's own bound on a grasp search of one part type (grasp_generation.cpp), checked here so
// that a fill is refused before its physics rather than after.
double GraspWork(const grasping::Gripper& gripper, const grasping::GraspOptions& o, size_t triangles) {
  const double candidates = double(o.candidates);
  if (std::holds_alternative<grasping::SuctionCup>(gripper)) return candidates * double(o.surface_samples);
  return candidates * (double(triangles) + 2.0 * double(o.surface_samples) * double(o.approaches_per_pair));
}

}  // namespace

StatusOr<service::ScenePickRequest> BinPicksFromProto(const v1::BinPicks& picks) {
  RETURN_IF_ERROR(RequireId(picks.mount_id(), "picks.mount_id"));
  v1::CheckPicksRequest as_call;
  as_call.set_mount_id(picks.mount_id());
  *as_call.mutable_gripper() = picks.gripper();
  *as_call.mutable_grasp_options() = picks.grasp_options();
  *as_call.mutable_pick_options() = picks.pick_options();
  auto request = ParseCheckPicksRequest(as_call);
  if (!request.ok()) return request.status().WithFieldPrefix("picks");
  Status checked = CheckGraspOptions(request->grasp_options);
  if (checked.ok()) checked = CheckPickOptions(*request);
  if (!checked.ok()) return checked.WithFieldPrefix("picks");
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
    if (GraspWork(picks.gripper, picks.grasp_options, part.mesh.triangles.size()) > kMaxGraspWork) {
      return ResourceExhausted("picks.grasp_options.candidates",
                               "the grasp search of part '" + part.name + "' would pass the bound of 2e9 " +
                                   "(candidates x surface samples; docs/GRASPING.md); ask fewer");
    }
  }
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
