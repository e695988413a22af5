#pragma once
// Where a mounted robot puts its sensor for commanded joints: the pose a robot-held scan casts from.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot_registry {
class RobotRegistry;
}

namespace vscan::service {

// A robot-held sensor: where the commanded joints put it and the joints the arm reached.
struct RobotPlacement {
  Pose3 commanded_world_from_sensor = Pose3::Identity();
  Eigen::VectorXd achieved_joint_positions;
  std::string mount_id;
};

// The mount must stand in scene_id. Encoder noise is applied when noise_seed is set. Errors name
// "mount_id" or "joint_positions".
StatusOr<RobotPlacement> PlaceRobotSensor(robot_registry::RobotRegistry& robots, const std::string& scene_id,
                                          const std::string& mount_id, const Eigen::VectorXd& joint_positions,
                                          std::optional<uint64_t> noise_seed, Pose3* world_from_sensor);

}  // namespace vscan::service
