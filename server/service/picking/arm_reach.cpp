#include "service/picking/arm_reach.h"

#include "service/robot/grasp_reach.h"
#include "service/robot/robot_collision.h"

namespace vscan::service {

grasping::ReachCheck ArmReach(ServiceContext& context, std::shared_ptr<const robot_registry::MountedRobot> mounted,
                              const grasping::Gripper& gripper, std::chrono::microseconds ik_time_budget,
                              double table_angle_deg) {
  robot_registry::IkSettings settings;
  settings.time_budget = ik_time_budget;
  return [&context, mounted, gripper, settings, table_angle_deg](
             const Pose3& world_from_tool, const Pose3& world_from_pregrasp) -> StatusOr<grasping::ReachAnswer> {
    ASSIGN_OR_RETURN(const GraspReach reach, SolveGraspReach(*mounted->chain, mounted->placement, gripper,
                                                             world_from_tool, world_from_pregrasp, settings));
    if (!reach.reached) {
      return grasping::ReachAnswer{grasping::PickFailure::kUnreachable,
                                   (reach.pregrasp_missed ? "pre-grasp: " : "") + reach.missed.failure.message(), {}};
    }
    for (const auto* joints : {&reach.grasp_joints, &reach.pregrasp_joints}) {
      ASSIGN_OR_RETURN(auto touch, FindRobotCollision(context, mounted->mount.mount_id, *joints, table_angle_deg));
      if (touch) return grasping::ReachAnswer{grasping::PickFailure::kArmCollision, *touch, {}};
    }
    return grasping::ReachAnswer{grasping::PickFailure::kNone, "", reach.grasp_joints};
  };
}

}  // namespace vscan::service
