#include "robot/kinematics_kernel.h"

namespace vscan::robot {

Pose3 ToolPose(const KinematicChain& chain, const double* q) {
  Pose3 T_base_frame = Pose3::Identity();
  const std::vector<ChainJoint>& joints = chain.joints();
  for (size_t i = 0; i < joints.size(); ++i) {
    T_base_frame = T_base_frame * joints[i].T_prev_joint;
    ApplyJointMotion(joints[i], q[i], T_base_frame);
  }
  return T_base_frame * chain.last_joint_from_tool();
}

Pose3 ToolPoseAndJacobian(const KinematicChain& chain, const double* q, JacobianBuffer* J) {
  const std::vector<ChainJoint>& joints = chain.joints();
  const int n = static_cast<int>(joints.size());
  J->resize(6, n);
  Pose3 T_base_frame = Pose3::Identity();
  for (int i = 0; i < n; ++i) {
    T_base_frame = T_base_frame * joints[i].T_prev_joint;
    // Axis direction and origin of joint i in the base frame; the origin goes in the top rows for now.
    J->col(i).head<3>() = T_base_frame.translation();
    J->col(i).tail<3>() = T_base_frame.linear() * joints[i].axis;
    ApplyJointMotion(joints[i], q[i], T_base_frame);
  }
  const Pose3 T_base_tool = T_base_frame * chain.last_joint_from_tool();
  const Eigen::Vector3d p_tool = T_base_tool.translation();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d z = J->col(i).tail<3>();
    if (joints[i].type == JointType::kPrismatic) {
      J->col(i).head<3>() = z;
      J->col(i).tail<3>().setZero();
    } else {
      J->col(i).head<3>() = z.cross(p_tool - J->col(i).head<3>());
    }
  }
  return T_base_tool;
}

}  // namespace vscan::robot
