#include "api/picking/pick_request.h"

#include <chrono>
#include <string_view>
#include <utility>

#include "api/transport/validate.h"
#include "grasping/public_field_names.h"

namespace vscan::api {
namespace {

// Proto3 reads an unset number as zero: zero keeps the default.
template <typename T, typename U>
void SetIfNonZero(T& target, U value) {
  if (value != 0) target = static_cast<T>(value);
}

// The service's names for what the request sets under pick_options; the engine's: PublicFieldName.
constexpr std::pair<std::string_view, std::string_view> kServiceFields[] = {
    {"body_length_m", "pick_options.body_length"},
    {"ik_time_budget_ms", "pick_options.ik_time_budget_ms"},
};

}  // namespace

Status InRequestTerms(const Status& status) {
  for (const auto& [service, request] : kServiceFields) {
    if (status.field() == service) return Status(status.code(), std::string(request), status.text());
  }
  const std::string_view field = grasping::PublicFieldName(status.field());
  if (field != status.field()) return Status(status.code(), std::string(field), status.text());
  return status;
}

StatusOr<grasping::Gripper> ParseGripper(const v1::Gripper& gripper) {
  switch (gripper.kind_case()) {
    case v1::Gripper::kSuction: {
      const v1::SuctionCup& in = gripper.suction();
      grasping::SuctionCup cup;
      SetIfNonZero(cup.diameter_m, in.diameter());
      SetIfNonZero(cup.stroke_m, in.stroke());
      SetIfNonZero(cup.max_tilt_deg, in.max_tilt_deg());
      SetIfNonZero(cup.min_flat_fraction, in.min_flat_fraction());
      RETURN_IF_ERROR(InRequestTerms(grasping::ValidateGripper(cup)));
      return grasping::Gripper(cup);
    }
    case v1::Gripper::kJaws: {
      const v1::ParallelJaws& in = gripper.jaws();
      grasping::ParallelJaws jaws;
      SetIfNonZero(jaws.min_opening_m, in.min_opening());
      SetIfNonZero(jaws.max_opening_m, in.max_opening());
      SetIfNonZero(jaws.finger_width_m, in.finger_width());
      SetIfNonZero(jaws.finger_depth_m, in.finger_depth());
      SetIfNonZero(jaws.max_friction_angle_deg, in.max_friction_angle_deg());
      SetIfNonZero(jaws.finger_length_m, in.finger_length());
      SetIfNonZero(jaws.finger_thickness_m, in.finger_thickness());
      RETURN_IF_ERROR(InRequestTerms(grasping::ValidateGripper(jaws)));
      return grasping::Gripper(jaws);
    }
    default:
      return InvalidArgument("gripper", "required: suction or jaws");
  }
}

grasping::GraspOptions ParseGraspOptions(const v1::GraspOptions& options) {
  grasping::GraspOptions out;
  SetIfNonZero(out.max_grasps, options.max_grasps());
  SetIfNonZero(out.seed, options.seed());
  SetIfNonZero(out.candidates, options.candidates());
  SetIfNonZero(out.surface_samples, options.surface_samples());
  return out;
}

StatusOr<service::ScenePickRequest> ParseCheckPicksRequest(const v1::CheckPicksRequest& request) {
  service::ScenePickRequest out;
  RETURN_IF_ERROR(RequireId(request.mount_id(), "mount_id"));
  for (int i = 0; i < request.part_object_ids_size(); ++i) {
    RETURN_IF_ERROR(RequireId(request.part_object_ids(i), "part_object_ids[" + std::to_string(i) + "]"));
  }
  out.mount_id = request.mount_id();
  out.part_object_ids.assign(request.part_object_ids().begin(), request.part_object_ids().end());
  ASSIGN_OR_RETURN(out.gripper, ParseGripper(request.gripper()));
  out.grasp_options = ParseGraspOptions(request.grasp_options());
  const v1::PickOptions& pick = request.pick_options();
  SetIfNonZero(out.pick_options.sweep.approach_m, pick.approach_distance());
  SetIfNonZero(out.pick_options.max_approach_tilt_deg, pick.max_approach_tilt_deg());
  SetIfNonZero(out.pick_options.cover_distance_m, pick.cover_distance());
  SetIfNonZero(out.pick_options.max_reach_checks, pick.max_reach_checks());
  out.pick_options.seed = out.grasp_options.seed;
  out.body_length_m = pick.body_length();
  if (pick.ik_time_budget_ms() != 0) out.ik_time_budget = std::chrono::milliseconds(pick.ik_time_budget_ms());
  return out;
}

}  // namespace vscan::api
