// RobotService.ForwardKinematics and InverseKinematics, in a robot's base frame or a mount's world.

#include <cmath>
#include <optional>

#include "api/robot/ik_request.h"
#include "api/robot/robot_convert.h"
#include "api/robot/robot_service.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "service/robot/inverse_kinematics.h"
#include "robot/forward_kinematics.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

using service::ArmTarget;

// The arm the request names: ids checked here, looked up by the service layer.
StatusOr<ArmTarget> ResolveTarget(robot_registry::RobotRegistry& robots, const std::string& robot_id,
                                  const std::string& mount_id) {
  if (!robot_id.empty()) RETURN_IF_ERROR(RequireId(robot_id, "robot_id"));
  if (!mount_id.empty()) RETURN_IF_ERROR(RequireId(mount_id, "mount_id"));
  return service::ResolveArm(robots, robot_id, mount_id);
}

StatusOr<std::optional<uint64_t>> NoiseSeed(const ArmTarget& target, bool apply, uint64_t seed) {
  if (!apply) return std::optional<uint64_t>();
  if (!target.mounted) {
    return InvalidArgument("apply_encoder_noise: needs mount_id (encoder sigma belongs to a mount)");
  }
  return std::optional<uint64_t>(seed);
}

Eigen::VectorXd ToVector(const google::protobuf::RepeatedField<double>& values) {
  return Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
}

// The solver names the goal "goal"; the request names it by the field that carried it.
Status RenameGoal(const Status& failure, const v1::InverseKinematicsRequest& request) {
  std::string field = "tool_pose";
  if (request.goal_case() == v1::InverseKinematicsRequest::kLookFrom) field = "look_from";
  if (request.goal_case() == v1::InverseKinematicsRequest::kToolPosition) field = "tool_position";
  const std::string& named = failure.field();
  if (named == "goal" || named.starts_with("goal.")) {
    return Status(failure.code(), field + named.substr(4), failure.text());
  }
  return Status(failure.code(), field, failure.message());
}

}  // namespace

grpc::ServerUnaryReactor* RobotService::ForwardKinematics(grpc::CallbackServerContext* ctx,
                                                          const v1::ForwardKinematicsRequest* request,
                                                          v1::ForwardKinematicsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ForwardKinematics", [&]() -> Status {
    ASSIGN_OR_RETURN(const ArmTarget target, ResolveTarget(context_.robots, request->robot_id(), request->mount_id()));
    ASSIGN_OR_RETURN(const auto noise_seed,
                     NoiseSeed(target, request->apply_encoder_noise(), request->encoder_noise_seed()));
    const Eigen::VectorXd q = ToVector(request->joint_positions());
    ASSIGN_OR_RETURN(const robot_registry::ArmState state,
                     robot_registry::CommandJoints(*target.chain, target.placement, q, "joint_positions", noise_seed));
    ASSIGN_OR_RETURN(const auto links, robot::ChainLinkPoses(*target.chain, q));
    vscan::ToProto(state.commanded_pose, response->mutable_tool_pose());
    for (const robot::LinkPose& link : links) {
      v1::LinkPose* out = response->add_link_poses();
      out->set_link(link.link);
      vscan::ToProto(target.placement.frame_from_base * link.base_from_link, out->mutable_pose());
    }
    ToProto(state.achieved, response->mutable_achieved_joint_positions());
    vscan::ToProto(state.achieved_pose, response->mutable_achieved_tool_pose());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* RobotService::InverseKinematics(grpc::CallbackServerContext* ctx,
                                                          const v1::InverseKinematicsRequest* request,
                                                          v1::InverseKinematicsResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "InverseKinematics", context_.call_workers, [=, this]() -> Status {
    ASSIGN_OR_RETURN(const ArmTarget target, ResolveTarget(context_.robots, request->robot_id(), request->mount_id()));
    ASSIGN_OR_RETURN(const IkRequestPlan plan, ParseInverseKinematicsRequest(*request));
    ASSIGN_OR_RETURN(const auto noise_seed,
                     NoiseSeed(target, request->apply_encoder_noise(), request->encoder_noise_seed()));
    ASSIGN_OR_RETURN(const service::CheckedIkAnswer checked,
                     service::SolveIkAvoidingCollisions(context_, target, plan.goal, ToVector(request->seed()), plan.settings,
                                                        request->avoid_collisions()));
    const robot_registry::IkAnswer& answer = checked.answer;
    if (!answer.reached && !request->allow_partial()) {
      return RenameGoal(answer.failure, *request).WithCode(StatusCode::kOutOfRange);
    }
    if (checked.collision && !request->allow_partial()) {
      return FailedPrecondition("avoid_collisions: every solution found in " + std::to_string(checked.checks) +
                                " tries collides; the last: " + *checked.collision);
    }
    if (checked.collision) response->set_collision(*checked.collision);
    response->set_collision_checks(checked.checks);

    const robot::IkResult& r = answer.result;
    ToProto(r.joint_positions, response->mutable_joint_positions());
    vscan::ToProto(answer.frame_from_tool, response->mutable_tool_pose());
    response->set_position_error(r.position_error);
    response->set_orientation_error_rad(r.orientation_error);
    response->set_reached(answer.reached);
    response->set_miss_distance(answer.miss_distance);
    response->set_iterations(static_cast<uint32_t>(r.iterations));
    response->set_restarts(static_cast<uint32_t>(r.restarts));
    response->set_solve_ms(r.elapsed_seconds * 1e3);
    ASSIGN_OR_RETURN(
        const robot_registry::ArmState state,
        robot_registry::CommandJoints(*target.chain, target.placement, r.joint_positions, "joint_positions",
                                      noise_seed));
    ToProto(state.achieved, response->mutable_achieved_joint_positions());
    vscan::ToProto(state.achieved_pose, response->mutable_achieved_tool_pose());
    return Status::Ok();
  });
}

}  // namespace vscan::api
