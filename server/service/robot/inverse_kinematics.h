#pragma once
// Inverse kinematics as a request asks for it: in a robot's base frame or a mount's world, and,
// when collisions are to be avoided, retried from random seeds until a solution touches nothing.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "robot/ik_types.h"
#include "robot_registry/arm_kinematics.h"
#include "robot_registry/robot_registry.h"
#include "service/context/service_context.h"

namespace vscan::service {

// A chain and where it stands: the robot's base frame, or the world of a mount.
struct ArmTarget {
  std::shared_ptr<const robot::KinematicChain> chain;
  robot_registry::Placement placement;
  bool mounted = false;
  std::string mount_id;
  std::string scene_id;
};

// The mount's arm when mount_id is set (robot_id, if set too, must be its robot), else the robot's.
// Errors name "robot_id" or "mount_id".
StatusOr<ArmTarget> ResolveArm(robot_registry::RobotRegistry& robots, const std::string& robot_id,
                               const std::string& mount_id);

// A solution and, with avoid_collisions, what it touches.
struct CheckedIkAnswer {
  robot_registry::IkAnswer answer;
  std::optional<std::string> collision;
  uint32_t checks = 0;
};

// Solves; with avoid_collisions (a mounted arm only), retries from random seeds within the one
// time budget until a reached solution touches nothing. Keeps the first unreached answer when
// nothing was reached.
StatusOr<CheckedIkAnswer> SolveIkAvoidingCollisions(ServiceContext& context, const ArmTarget& target,
                                                    const robot::IkGoal& goal, const Eigen::VectorXd& seed,
                                                    const robot_registry::IkSettings& settings, bool avoid_collisions);

}  // namespace vscan::service
