// RobotService.ForwardKinematics and InverseKinematics, in a robot's base frame or a mount's world.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>

#include "api/robot_collision.h"
#include "api/robot_convert.h"
#include "api/robot_service.h"
#include "api/unary.h"
#include "api/validate.h"
#include "robot/forward_kinematics.h"
#include "vscan/common/physical_limits.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

constexpr double kDefaultTolerance = 1e-5;
constexpr double kDefaultTimeoutMs = 50.0;
constexpr double kMaxTimeoutMs = 5000.0;

// The chain and where it stands: the robot's base frame, or the world of a mount.
struct Target {
  std::shared_ptr<const robot::KinematicChain> chain;
  robots::Placement placement;
  bool mounted = false;
  std::string mount_id;
  std::string scene_id;
};

StatusOr<Target> ResolveTarget(robots::RobotRegistry& robots, const std::string& robot_id,
                               const std::string& mount_id) {
  Target target;
  if (mount_id.empty()) {
    if (robot_id.empty()) return InvalidArgument("robot_id: required (or mount_id for world coordinates)");
    RETURN_IF_ERROR(RequireId(robot_id, "robot_id"));
    ASSIGN_OR_RETURN(target.chain, robots.Chain(robot_id));
    return target;
  }
  RETURN_IF_ERROR(RequireId(mount_id, "mount_id"));
  ASSIGN_OR_RETURN(robots::MountedRobot mounted, robots.Mount(mount_id));
  if (!robot_id.empty() && robot_id != mounted.mount.robot_id) {
    return InvalidArgument("robot_id: mount '" + mount_id + "' holds robot '" + mounted.mount.robot_id + "', not '" +
                           robot_id + "'");
  }
  target.chain = std::move(mounted.chain);
  target.placement = std::move(mounted.placement);
  target.mounted = true;
  target.mount_id = mount_id;
  target.scene_id = mounted.mount.scene_id;
  return target;
}

StatusOr<std::optional<uint64_t>> NoiseSeed(const Target& target, bool apply, uint64_t seed) {
  if (!apply) return std::optional<uint64_t>();
  if (!target.mounted) {
    return InvalidArgument("apply_encoder_noise: needs mount_id (encoder sigma belongs to a mount)");
  }
  return std::optional<uint64_t>(seed);
}

Eigen::VectorXd ToVector(const google::protobuf::RepeatedField<double>& values) {
  return Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
}

StatusOr<robot::IkGoal> GoalFromRequest(const v1::InverseKinematicsRequest& request) {
  switch (request.goal_case()) {
    case v1::InverseKinematicsRequest::kToolPose: {
      ASSIGN_OR_RETURN(const Pose3 pose, PoseFromProto(request.tool_pose(), "tool_pose"));
      return robot::PoseGoal(pose);
    }
    case v1::InverseKinematicsRequest::kLookFrom: {
      const auto& look = request.look_from();
      if (!look.has_position()) return InvalidArgument("look_from.position: required");
      if (!look.has_target()) return InvalidArgument("look_from.target: required");
      const Eigen::Vector3d position = FromProto(look.position());
      const Eigen::Vector3d target = FromProto(look.target());
      RETURN_IF_ERROR(CheckPosition(position, "look_from.position"));
      RETURN_IF_ERROR(CheckPosition(target, "look_from.target"));
      return robot::LookAtGoal(position, target, "look_from");
    }
    case v1::InverseKinematicsRequest::kToolPosition: {
      const Eigen::Vector3d position = FromProto(request.tool_position());
      RETURN_IF_ERROR(CheckPosition(position, "tool_position"));
      return robot::PositionGoal(position);
    }
    case v1::InverseKinematicsRequest::GOAL_NOT_SET: break;
  }
  return InvalidArgument("tool_pose: required (or look_from, or tool_position)");
}

StatusOr<double> PositiveOrDefault(double value, double fallback, double max, const char* field, const char* unit) {
  if (value == 0.0) return fallback;
  if (!std::isfinite(value) || value < 0 || value > max) {
    char bound[32];
    std::snprintf(bound, sizeof(bound), "%g", max);
    return InvalidArgument(std::string(field) + ": must be a finite number in (0, " + bound + "] " + unit +
                           " (0 means the default)");
  }
  return value;
}

StatusOr<robots::IkSettings> SettingsFromRequest(const v1::InverseKinematicsRequest& request) {
  robots::IkSettings settings;
  switch (request.method()) {
    case v1::IK_METHOD_UNSPECIFIED:
    case v1::IK_METHOD_DEFAULT: settings.solver = robots::IkSolverKind::kDefault; break;
    case v1::IK_METHOD_GRADIENT_DESCENT: settings.solver = robots::IkSolverKind::kGradientDescent; break;
    default: return InvalidArgument("method: unknown value " + std::to_string(request.method()));
  }
  ASSIGN_OR_RETURN(settings.position_tolerance,
                   PositiveOrDefault(request.tolerance(), kDefaultTolerance, 1.0, "tolerance", "m"));
  ASSIGN_OR_RETURN(settings.orientation_tolerance,
                   PositiveOrDefault(request.orientation_tolerance_rad(), kDefaultTolerance, std::numbers::pi,
                                     "orientation_tolerance_rad", "rad"));
  ASSIGN_OR_RETURN(const double timeout_ms,
                   PositiveOrDefault(request.timeout_ms(), kDefaultTimeoutMs, kMaxTimeoutMs, "timeout_ms", "ms"));
  settings.time_budget = std::chrono::microseconds(static_cast<int64_t>(timeout_ms * 1000.0));
  return settings;
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

// A solution and, with avoid_collisions, what it touches.
struct CheckedAnswer {
  robots::IkAnswer answer;
  std::optional<std::string> collision;
  uint32_t checks = 0;
};

// Solves; with avoid_collisions, retries from random seeds within the one time budget until a
// reached solution touches nothing. Keeps the first unreached answer when nothing was reached.
StatusOr<CheckedAnswer> SolveAvoidingCollisions(ServiceContext& context, const Target& target,
                                                const robot::IkGoal& goal, const Eigen::VectorXd& seed,
                                                const robots::IkSettings& settings, bool avoid_collisions) {
  CheckedAnswer out;
  ASSIGN_OR_RETURN(out.answer, robots::SolveInPlacement(*target.chain, target.placement, goal, seed, settings));
  if (!avoid_collisions || !out.answer.reached) return out;
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + settings.time_budget;
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(target.scene_id));
  std::mt19937_64 rng(0x5eed);
  robots::IkSettings retry = settings;
  for (robots::IkAnswer attempt = out.answer;;) {
    ASSIGN_OR_RETURN(auto collision, FindRobotCollision(context, target.mount_id, attempt.result.joint_positions,
                                                        scene.table.angle_deg));
    ++out.checks;
    if (attempt.reached) {
      out.answer = std::move(attempt);
      out.collision = std::move(collision);
      if (!out.collision) return out;
    }
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now());
    if (left.count() <= 0) return out;
    retry.time_budget = left;
    ASSIGN_OR_RETURN(attempt, robots::SolveInPlacement(*target.chain, target.placement, goal,
                                                       robot::RandomJointPositions(*target.chain, rng), retry));
    if (!attempt.reached) return out;
  }
}

}  // namespace

grpc::ServerUnaryReactor* RobotService::ForwardKinematics(grpc::CallbackServerContext* ctx,
                                                          const v1::ForwardKinematicsRequest* request,
                                                          v1::ForwardKinematicsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ForwardKinematics", [&]() -> Status {
    ASSIGN_OR_RETURN(const Target target, ResolveTarget(context_.robots, request->robot_id(), request->mount_id()));
    ASSIGN_OR_RETURN(const auto noise_seed,
                     NoiseSeed(target, request->apply_encoder_noise(), request->encoder_noise_seed()));
    const Eigen::VectorXd q = ToVector(request->joint_positions());
    ASSIGN_OR_RETURN(const robots::ArmState state,
                     robots::CommandJoints(*target.chain, target.placement, q, "joint_positions", noise_seed));
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
  return RunUnary(ctx, context_.options.token, "InverseKinematics", [&]() -> Status {
    ASSIGN_OR_RETURN(const Target target, ResolveTarget(context_.robots, request->robot_id(), request->mount_id()));
    ASSIGN_OR_RETURN(const robot::IkGoal goal, GoalFromRequest(*request));
    ASSIGN_OR_RETURN(const robots::IkSettings settings, SettingsFromRequest(*request));
    ASSIGN_OR_RETURN(const auto noise_seed,
                     NoiseSeed(target, request->apply_encoder_noise(), request->encoder_noise_seed()));
    if (request->avoid_collisions() && !target.mounted) {
      return InvalidArgument("avoid_collisions: needs mount_id (collisions are with the mount's scene)");
    }
    ASSIGN_OR_RETURN(const CheckedAnswer checked,
                     SolveAvoidingCollisions(context_, target, goal, ToVector(request->seed()), settings,
                                             request->avoid_collisions()));
    const robots::IkAnswer& answer = checked.answer;
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
        const robots::ArmState state,
        robots::CommandJoints(*target.chain, target.placement, r.joint_positions, "joint_positions", noise_seed));
    ToProto(state.achieved, response->mutable_achieved_joint_positions());
    vscan::ToProto(state.achieved_pose, response->mutable_achieved_tool_pose());
    return Status::Ok();
  });
}

}  // namespace vscan::api
