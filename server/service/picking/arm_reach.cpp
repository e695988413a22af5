#include "service/picking/arm_reach.h"

#include "robot/ik_types.h"
#include "robot_registry/arm_kinematics.h"
#include "service/robot/robot_collision.h"

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

grasping::ReachCheck ArmReach(ServiceContext& context, std::shared_ptr<const robot_registry::MountedRobot> mounted,
                              const grasping::Gripper& gripper, std::chrono::microseconds ik_time_budget,
                              double table_angle_deg) {
  robot_registry::IkSettings settings;
  settings.time_budget = ik_time_budget;
  return [&context, mounted, gripper, settings, table_angle_deg](
             const Pose3& world_from_tool, const Pose3& world_from_pregrasp) -> StatusOr<grasping::ReachAnswer> {
    ASSIGN_OR_RETURN(const robot_registry::IkAnswer grasp,
                     robot_registry::SolveInPlacement(*mounted->chain, mounted->placement,
                                                      ToolGoal(gripper, world_from_tool), {}, settings));
    if (!grasp.reached) return grasping::ReachAnswer{grasping::PickFailure::kUnreachable, grasp.failure.message(), {}};
    ASSIGN_OR_RETURN(const robot_registry::IkAnswer pregrasp,
                     robot_registry::SolveInPlacement(*mounted->chain, mounted->placement,
                                                      ToolGoal(gripper, world_from_pregrasp),
                                                      grasp.result.joint_positions, settings));
    if (!pregrasp.reached) {
      return grasping::ReachAnswer{grasping::PickFailure::kUnreachable, "pre-grasp: " + pregrasp.failure.message(), {}};
    }
    for (const auto* joints : {&grasp.result.joint_positions, &pregrasp.result.joint_positions}) {
      ASSIGN_OR_RETURN(auto touch, FindRobotCollision(context, mounted->mount.mount_id, *joints, table_angle_deg));
      if (touch) return grasping::ReachAnswer{grasping::PickFailure::kArmCollision, *touch, {}};
    }
    return grasping::ReachAnswer{grasping::PickFailure::kNone, "", grasp.result.joint_positions};
  };
}

}  // namespace vscan::service
