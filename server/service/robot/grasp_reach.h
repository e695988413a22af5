#pragma once
// Inverse kinematics of a placed arm to a grasp and then to its pre-grasp (a cup's rotation about
// its axis left free): the reach test of a pick, without the arm's collisions. ArmReach adds those
// for a mounted robot; a dataset's picks use it as it is.

#include <memory>

#include <Eigen/Core>

#include "grasping/gripper.h"
#include "grasping/pick_checks.h"
#include "robot/chain.h"
#include "robot_registry/arm_kinematics.h"

namespace vscan::service {

struct GraspReach {
  bool reached = false;          // both solved within tolerance
  bool pregrasp_missed = false;  // not reached: the grasp was, the pre-grasp was not
  robot_registry::IkAnswer missed;  // not reached: the solve that missed
  Eigen::VectorXd grasp_joints;
  Eigen::VectorXd pregrasp_joints;
};

StatusOr<GraspReach> SolveGraspReach(const robot::KinematicChain& chain, const robot_registry::Placement& placement,
                                     const grasping::Gripper& gripper, const Pose3& world_from_tool,
                                     const Pose3& world_from_pregrasp, const robot_registry::IkSettings& settings);

// SolveGraspReach as CheckPicks' reach test, callable from several threads at once. A miss is
// kUnreachable with the distance it misses by (nothing timed, so the same settings give the same words).
grasping::ReachCheck KinematicReach(std::shared_ptr<const robot::KinematicChain> chain,
                                    robot_registry::Placement placement, grasping::Gripper gripper,
                                    robot_registry::IkSettings settings);

}  // namespace vscan::service
