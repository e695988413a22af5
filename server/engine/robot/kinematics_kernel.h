#pragma once
// Unchecked, allocation-free kinematics for inner loops. Callers validate q beforehand.

#include <cmath>

#include <Eigen/Core>

#include "robot/chain.h"
#include "vscan/common/pose.h"

namespace vscan::robot {

// Geometric Jacobian of the tool origin: rows 0-2 linear velocity, rows 3-5 angular velocity,
// both expressed in the base frame; one column per moving joint.
using JacobianBuffer = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxChainJoints>;
using JointBuffer = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxChainJoints, 1>;

// T <- T * (motion of joint j at position q).
inline void ApplyJointMotion(const ChainJoint& j, double q, Pose3& T) {
  if (j.type == JointType::kPrismatic) {
    T.translation() += T.linear() * (j.axis * q);
    return;
  }
  if (j.axis_index < 0) {
    T.linear() = T.linear() * Eigen::AngleAxisd(q, j.axis).toRotationMatrix();
    return;
  }
  // Right-multiplying by a rotation about coordinate axis k mixes the two other columns.
  const double angle = j.axis_sign * q;
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const int a = (j.axis_index + 1) % 3;
  const int b = (j.axis_index + 2) % 3;
  auto R = T.linear();
  const Eigen::Vector3d col_a = R.col(a);
  R.col(a) = c * col_a + s * R.col(b);
  R.col(b) = c * R.col(b) - s * col_a;
}

// base_from_tool at q (chain.dof() values).
Pose3 ToolPose(const KinematicChain& chain, const double* q);

// base_from_tool at q, and the Jacobian into *J (resized to 6 x dof, no allocation).
Pose3 ToolPoseAndJacobian(const KinematicChain& chain, const double* q, JacobianBuffer* J);

}  // namespace vscan::robot
