#include "service/robot/robot_placement.h"

#include "robot_registry/robot_registry.h"
#include "vscan/common/physical_limits.h"

namespace vscan::service {

StatusOr<RobotPlacement> PlaceRobotSensor(robot_registry::RobotRegistry& robots, const std::string& scene_id,
                                          const std::string& mount_id, const Eigen::VectorXd& joint_positions,
                                          std::optional<uint64_t> noise_seed, Pose3* world_from_sensor) {
  ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, robots.Mount(mount_id));
  if (mounted.mount.scene_id != scene_id) {
    return FailedPrecondition("mount_id", "mount '" + mount_id + "' is in scene '" + mounted.mount.scene_id +
                              "', not in scene_id '" + scene_id + "'");
  }
  ASSIGN_OR_RETURN(const robot_registry::ArmState state,
                   robot_registry::CommandJoints(*mounted.chain, mounted.placement, joint_positions, "joint_positions",
                                                 noise_seed));
  // Each part is bounded where it entered; their composition is checked as well.
  RETURN_IF_ERROR(CheckPosition(state.achieved_pose.translation(), "mount_id (the sensor position it reaches)"));
  *world_from_sensor = state.achieved_pose;
  return RobotPlacement{state.commanded_pose, state.achieved, mount_id};
}

}  // namespace vscan::service
