#pragma once
// Checked forward kinematics and Jacobian of a chain.

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "robot/chain.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot {

// Rows 0-2: linear velocity of the tool origin; rows 3-5: angular velocity; base frame.
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic>;

// InvalidArgument "<field>: ..." for a wrong count or a non-finite value; OutOfRange
// "<field>[i]: ... outside [lo, hi]" for a value beyond the joint's limits.
Status ValidateJointPositions(const KinematicChain& chain, const Eigen::VectorXd& q,
                              std::string_view field = "joint_positions");

// base_from_tool at q.
StatusOr<Pose3> ForwardKinematics(const KinematicChain& chain, const Eigen::VectorXd& q);

// Geometric Jacobian at q, computed analytically from the joint axes.
StatusOr<Jacobian> GeometricJacobian(const KinematicChain& chain, const Eigen::VectorXd& q);

struct LinkPose {
  std::string link;
  Pose3 base_from_link;
};

// Poses of the base link and of every link along the chain at q, base first.
StatusOr<std::vector<LinkPose>> ChainLinkPoses(const KinematicChain& chain, const Eigen::VectorXd& q);

}  // namespace vscan::robot
