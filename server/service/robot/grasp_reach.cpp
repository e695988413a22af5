#include "service/robot/grasp_reach.h"

#include <cstdio>
#include <variant>

#include "robot/ik_types.h"

namespace vscan::service {
namespace {

robot::IkGoal ToolGoal(const grasping::Gripper& gripper, const Pose3& world_from_tool) {
  // A cup is round: its rotation about the approach is free.
  if (std::holds_alternative<grasping::SuctionCup>(gripper)) {
    robot::IkGoal goal;
    goal.kind = robot::IkGoalKind::kLookAt;
    goal.base_from_tool = world_from_tool;
    goal.view_direction = world_from_tool.linear().col(2);
    return goal;
  }
  return robot::PoseGoal(world_from_tool);
}

}  // namespace

StatusOr<GraspReach> SolveGraspReach(const robot::KinematicChain& chain, const robot_registry::Placement& placement,
                                     const grasping::Gripper& gripper, const Pose3& world_from_tool,
                                     const Pose3& world_from_pregrasp, const robot_registry::IkSettings& settings) {
  GraspReach out;
  ASSIGN_OR_RETURN(robot_registry::IkAnswer grasp,
                   robot_registry::SolveInPlacement(chain, placement, ToolGoal(gripper, world_from_tool), {}, settings));
  if (!grasp.reached) {
    out.missed = std::move(grasp);
    return out;
  }
  ASSIGN_OR_RETURN(robot_registry::IkAnswer pregrasp,
                   robot_registry::SolveInPlacement(chain, placement, ToolGoal(gripper, world_from_pregrasp),
                                                    grasp.result.joint_positions, settings));
  if (!pregrasp.reached) {
    out.pregrasp_missed = true;
    out.missed = std::move(pregrasp);
    return out;
  }
  out.reached = true;
  out.grasp_joints = std::move(grasp.result.joint_positions);
  out.pregrasp_joints = std::move(pregrasp.result.joint_positions);
  return out;
}

grasping::ReachCheck KinematicReach(std::shared_ptr<const robot::KinematicChain> chain,
                                    robot_registry::Placement placement, grasping::Gripper gripper,
                                    robot_registry::IkSettings settings) {
  return [chain = std::move(chain), placement = std::move(placement), gripper, settings](
             const Pose3& world_from_tool, const Pose3& world_from_pregrasp) -> StatusOr<grasping::ReachAnswer> {
    ASSIGN_OR_RETURN(GraspReach reach,
                     SolveGraspReach(*chain, placement, gripper, world_from_tool, world_from_pregrasp, settings));
    if (reach.reached) return grasping::ReachAnswer{grasping::PickFailure::kNone, "", std::move(reach.grasp_joints)};
    char text[160];
    std::snprintf(text, sizeof(text), "%sthe arm's nearest pose misses by %.1f mm", reach.pregrasp_missed ? "pre-grasp: " : "",
                  reach.missed.miss_distance * 1e3);
    return grasping::ReachAnswer{grasping::PickFailure::kUnreachable, text, {}};
  };
}

}  // namespace vscan::service
