#include "service/model/pose_prior.h"

#include <string>

#include <Eigen/Geometry>

#include "robot_registry/arm_kinematics.h"

namespace vscan::service {
namespace {

// The smallest standard deviation a known pose is given (radians, metres): it keeps the
// information finite, far above what scans of any real surface can pin.
constexpr double kFloorSigma = 1e-6;
constexpr double kJointStep = 1e-6;  // radians or metres, for the numerical Jacobian

Eigen::Matrix<double, 6, 1> RightPerturbation(const Pose3& from, const Pose3& to) {
  const Pose3 e = from.inverse() * to;
  const Eigen::AngleAxisd turn(e.linear());
  Eigen::Matrix<double, 6, 1> v;
  v << turn.angle() * turn.axis(), e.translation();
  return v;
}

}  // namespace

StatusOr<PoseInformation> CommandedPoseInformation(const robot_registry::MountedRobot& mounted,
                                                   const Eigen::VectorXd& commanded, bool encoder_noise) {
  if (commanded.size() != mounted.chain->dof() || !commanded.allFinite()) {
    return InvalidArgument("commanded_joints", "expected " + std::to_string(mounted.chain->dof()) +
                                                   " finite joint values, got " + std::to_string(commanded.size()));
  }
  PoseInformation covariance = PoseInformation::Identity() * (kFloorSigma * kFloorSigma);
  const Eigen::VectorXd& sigma = mounted.placement.encoder_sigma;
  if (encoder_noise && sigma.size() > 0 && sigma.size() == commanded.size()) {
    ASSIGN_OR_RETURN(const robot_registry::ArmState base,
                     robot_registry::CommandJoints(*mounted.chain, mounted.placement, commanded, "commanded_joints"));
    const Eigen::VectorXd upper = mounted.chain->UpperLimits();
    for (Eigen::Index j = 0; j < commanded.size(); ++j) {
      if (sigma[j] <= 0) continue;
      Eigen::VectorXd moved = commanded;
      // Step away from the nearer limit, so that the clamp into the limits does not flatten it.
      const double step = commanded[j] + kJointStep <= upper[j] ? kJointStep : -kJointStep;
      moved[j] += step;
      ASSIGN_OR_RETURN(const robot_registry::ArmState turned,
                       robot_registry::CommandJoints(*mounted.chain, mounted.placement, moved, "commanded_joints"));
      const Eigen::Matrix<double, 6, 1> column = RightPerturbation(base.commanded_pose, turned.commanded_pose) / step;
      covariance += sigma[j] * sigma[j] * column * column.transpose();
    }
  }
  return PoseInformation(covariance.inverse());
}

}  // namespace vscan::service
