#pragma once
// Whether a mounted robot at given joint positions touches the scene (Bullet collision world).

#include <optional>
#include <string>

#include <Eigen/Core>

#include "service/context/service_context.h"

namespace vscan::service {

// Empty when the arm is clear of the scene (at table_angle_deg) and of itself beyond adjacent
// links; otherwise a description such as "link 'wrist_3_link' touches object 'bunny'".
StatusOr<std::optional<std::string>> FindRobotCollision(ServiceContext& context, const std::string& mount_id,
                                                        const Eigen::VectorXd& joint_positions,
                                                        double table_angle_deg);

}  // namespace vscan::service
