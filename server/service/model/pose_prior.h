#pragma once
// How firmly the pose a robot was told to reach is known: the encoder noise of the mount's joints
// (when the campaign applied it), carried to the sensor by the arm's Jacobian, as the information
// over the right perturbation (w, t) of the sensor pose that the pose graph weighs. An arm without
// encoder noise reaches its commanded pose exactly: that pose is then known to a micrometre.

#include <Eigen/Core>

#include "robot_registry/robot_registry.h"
#include "vscan/common/status.h"

namespace vscan::service {

using PoseInformation = Eigen::Matrix<double, 6, 6>;

// commanded: the joints the arm was told to take. INVALID_ARGUMENT when they do not fit the chain.
StatusOr<PoseInformation> CommandedPoseInformation(const robot_registry::MountedRobot& mounted,
                                                   const Eigen::VectorXd& commanded, bool encoder_noise);

}  // namespace vscan::service
