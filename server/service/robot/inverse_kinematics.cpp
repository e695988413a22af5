#include "service/robot/inverse_kinematics.h"

#include <chrono>
#include <random>

#include "service/robot/robot_collision.h"

namespace vscan::service {

StatusOr<ArmTarget> ResolveArm(robot_registry::RobotRegistry& robots, const std::string& robot_id,
                               const std::string& mount_id) {
  ArmTarget target;
  if (mount_id.empty()) {
    if (robot_id.empty()) return InvalidArgument("robot_id", "required (or mount_id for world coordinates)");
    ASSIGN_OR_RETURN(target.chain, robots.Chain(robot_id));
    return target;
  }
  ASSIGN_OR_RETURN(robot_registry::MountedRobot mounted, robots.Mount(mount_id));
  if (!robot_id.empty() && robot_id != mounted.mount.robot_id) {
    return InvalidArgument("robot_id", "mount '" + mount_id + "' holds robot '" + mounted.mount.robot_id +
                           "', not '" + robot_id + "'");
  }
  target.chain = std::move(mounted.chain);
  target.placement = std::move(mounted.placement);
  target.mounted = true;
  target.mount_id = mount_id;
  target.scene_id = mounted.mount.scene_id;
  return target;
}

StatusOr<CheckedIkAnswer> SolveIkAvoidingCollisions(ServiceContext& context, const ArmTarget& target,
                                                    const robot::IkGoal& goal, const Eigen::VectorXd& seed,
                                                    const robot_registry::IkSettings& settings, bool avoid_collisions) {
  if (avoid_collisions && !target.mounted) {
    return InvalidArgument("avoid_collisions", "needs mount_id (collisions are with the mount's scene)");
  }
  CheckedIkAnswer out;
  ASSIGN_OR_RETURN(out.answer, robot_registry::SolveInPlacement(*target.chain, target.placement, goal, seed, settings));
  if (!avoid_collisions || !out.answer.reached) return out;
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + settings.time_budget;
  ASSIGN_OR_RETURN(const store::SceneRecord scene, context.registry.catalogue().GetScene(target.scene_id));
  std::mt19937_64 rng(0x5eed);
  robot_registry::IkSettings retry = settings;
  for (robot_registry::IkAnswer attempt = out.answer;;) {
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
    ASSIGN_OR_RETURN(attempt, robot_registry::SolveInPlacement(*target.chain, target.placement, goal,
                                                              robot::RandomJointPositions(*target.chain, rng), retry));
    if (!attempt.reached) return out;
  }
}

}  // namespace vscan::service
