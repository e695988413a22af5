#include "robot/forward_kinematics.h"

#include <cmath>
#include <sstream>

#include "robot/kinematics_kernel.h"

namespace vscan::robot {
namespace {

std::string FormatDouble(double v) {
  std::ostringstream out;
  out.precision(10);
  out << v;
  return out.str();
}

}  // namespace

Status ValidateJointPositions(const KinematicChain& chain, const Eigen::VectorXd& q, std::string_view field) {
  const std::string f(field);
  if (q.size() != chain.dof()) {
    return InvalidArgument(f, "expected " + std::to_string(chain.dof()) + " values (one per joint of " +
                           chain.base_link() + " -> " + chain.tip_link() + "), got " + std::to_string(q.size()));
  }
  for (int i = 0; i < q.size(); ++i) {
    const std::string fi = f + "[" + std::to_string(i) + "]";
    if (!std::isfinite(q[i])) return InvalidArgument(fi, "NaN or infinite value");
    const ChainJoint& j = chain.joints()[i];
    if (q[i] < j.lower || q[i] > j.upper) {
      return OutOfRange(fi, FormatDouble(q[i]) + " outside [" + FormatDouble(j.lower) + ", " +
                        FormatDouble(j.upper) + "] of joint '" + j.name + "'");
    }
  }
  return Status::Ok();
}

StatusOr<Pose3> ForwardKinematics(const KinematicChain& chain, const Eigen::VectorXd& q) {
  RETURN_IF_ERROR(ValidateJointPositions(chain, q));
  return ToolPose(chain, q.data());
}

StatusOr<Jacobian> GeometricJacobian(const KinematicChain& chain, const Eigen::VectorXd& q) {
  RETURN_IF_ERROR(ValidateJointPositions(chain, q));
  JacobianBuffer J;
  ToolPoseAndJacobian(chain, q.data(), &J);
  return Jacobian(J);
}

StatusOr<std::vector<LinkPose>> ChainLinkPoses(const KinematicChain& chain, const Eigen::VectorXd& q) {
  RETURN_IF_ERROR(ValidateJointPositions(chain, q));
  std::vector<LinkPose> poses = {{chain.base_link(), Pose3::Identity()}};
  Pose3 T_base_link = Pose3::Identity();
  int joint = 0;
  for (const ChainSegment& s : chain.segments()) {
    T_base_link = T_base_link * s.T_parent_joint;
    if (s.type != JointType::kFixed) {
      ApplyJointMotion(chain.joints()[joint], q[joint], T_base_link);
      ++joint;
    }
    poses.push_back({s.child_link, T_base_link});
  }
  return poses;
}

}  // namespace vscan::robot
