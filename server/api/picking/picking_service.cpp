#include "api/picking/picking_service.h"

#include <chrono>
#include <cmath>

#include "api/picking/pick_request.h"
#include "api/transport/cancellable_unary.h"
#include "api/transport/validate.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

using Clock = std::chrono::steady_clock;

void ToProto(const grasping::Grasp& grasp, v1::Grasp* out) {
  *out->mutable_part_from_tool() = vscan::PoseToProto(grasp.part_from_tool);
  *out->mutable_approach() = vscan::ToProto(grasp.approach);
  out->set_quality(grasp.quality);
  out->set_opening(grasp.opening_m);
}

v1::PickFailure ToProto(grasping::PickFailure failure) {
  switch (failure) {
    case grasping::PickFailure::kCovered: return v1::PICK_FAILURE_COVERED;
    case grasping::PickFailure::kNoGrasp: return v1::PICK_FAILURE_NO_GRASP;
    case grasping::PickFailure::kGripperCollision: return v1::PICK_FAILURE_GRIPPER_COLLISION;
    case grasping::PickFailure::kUnreachable: return v1::PICK_FAILURE_UNREACHABLE;
    case grasping::PickFailure::kArmCollision: return v1::PICK_FAILURE_ARM_COLLISION;
    default: return v1::PICK_FAILURE_UNSPECIFIED;
  }
}

void ToResponse(const service::ScenePicks& picks, v1::CheckPicksResponse* response) {
  response->set_scene_id(picks.scene_id);
  uint32_t pickable = 0;
  for (const service::ObjectPick& pick : picks.parts) {
    v1::PartPick* out = response->add_parts();
    out->set_object_id(pick.object_id);
    out->set_label(pick.label);
    out->set_pickable(pick.verdict.pickable);
    out->set_failure(ToProto(pick.verdict.failure));
    out->set_detail(pick.verdict.detail);
    if (pick.verdict.pickable) {
      ++pickable;
      out->set_grasp_index(static_cast<uint32_t>(*pick.verdict.grasp));
      *out->mutable_world_from_tool() = vscan::PoseToProto(pick.verdict.world_from_tool);
      for (Eigen::Index j = 0; j < pick.verdict.joint_positions.size(); ++j) {
        out->add_joint_positions(pick.verdict.joint_positions[j]);
      }
    }
    out->set_covered_by_object_id(pick.covered_by_object_id);
    out->set_grasps_from_above(static_cast<uint32_t>(pick.verdict.grasps_from_above));
    out->set_grasps_clear(static_cast<uint32_t>(pick.verdict.grasps_clear));
    out->set_reach_checks(static_cast<uint32_t>(pick.verdict.reach_checks));
  }
  response->set_pickable(pickable);
  response->set_grasps_generated(static_cast<uint32_t>(picks.grasps_generated));
  response->set_elapsed_ms(picks.elapsed_s * 1000);
}

Status GenerateGraspsOf(service::ServiceContext& context, const v1::GenerateGraspsRequest& request,
                        v1::GenerateGraspsResponse* response) {
  const auto start = Clock::now();
  RETURN_IF_ERROR(RequireId(request.mesh_id(), "mesh_id"));
  const double scale = request.scale() == 0 ? 1.0 : request.scale();
  if (!std::isfinite(scale) || scale <= 0 || scale > 1000) return InvalidArgument("scale", "must be in (0, 1000]");
  ASSIGN_OR_RETURN(const grasping::Gripper gripper, ParseGripper(request.gripper()));
  ASSIGN_OR_RETURN(const auto mesh, context.registry.LoadMesh(request.mesh_id()));
  TriangleMesh scaled = *mesh;
  for (Eigen::Vector3f& v : scaled.vertices) v *= float(scale);
  ASSIGN_OR_RETURN(const auto grasps, grasping::GenerateGrasps(scaled, gripper, ParseGraspOptions(request.options())));
  for (const grasping::Grasp& grasp : grasps) ToProto(grasp, response->add_grasps());
  response->set_elapsed_ms(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  return Status::Ok();
}

}  // namespace

grpc::ServerUnaryReactor* PickingService::GenerateGrasps(grpc::CallbackServerContext* ctx,
                                                         const v1::GenerateGraspsRequest* request,
                                                         v1::GenerateGraspsResponse* response) {
  // Tens of milliseconds to a few seconds of sampling and ray casts: on the workers.
  return RunCancellableUnary(ctx, context_.options.token, "GenerateGrasps", context_.workers,
                             [=, this](const std::atomic<bool>&) -> Status {
                               return GenerateGraspsOf(context_, *request, response);
                             });
}

grpc::ServerUnaryReactor* PickingService::CheckPicks(grpc::CallbackServerContext* ctx,
                                                     const v1::CheckPicksRequest* request,
                                                     v1::CheckPicksResponse* response) {
  return RunCancellableUnary(ctx, context_.options.token, "CheckPicks", context_.workers,
                             [=, this](const std::atomic<bool>& cancel) -> Status {
                               ASSIGN_OR_RETURN(const service::ScenePickRequest parsed,
                                                ParseCheckPicksRequest(*request));
                               const auto picks = service::CheckScenePicks(context_, parsed, &cancel);
                               if (!picks.ok()) return InRequestTerms(picks.status());
                               ToResponse(*picks, response);
                               return Status::Ok();
                             });
}

}  // namespace vscan::api
