#pragma once
// Where a mounted robot puts its sensor for commanded joints: the pose a robot-held scan casts from.

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "robots/robot_registry.h"
#include "service/scan_plan.h"

namespace vscan::service {

// The mount must stand in scene_id. Encoder noise is applied when noise_seed is set. Errors name
// "mount_id" or "joint_positions".
StatusOr<RobotPlacement> PlaceRobotSensor(robots::RobotRegistry& robots, const std::string& scene_id,
                                          const std::string& mount_id, const Eigen::VectorXd& joint_positions,
                                          std::optional<uint64_t> noise_seed, Pose3* world_from_sensor);

}  // namespace vscan::service
