#pragma once
// A serial kinematic chain from a base link to a tip link, plus the tool mounted on the tip.

#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot {

// Upper bound on moving joints per chain; kinematics work in fixed-capacity buffers of this size.
inline constexpr int kMaxChainJoints = 32;

enum class JointType { kFixed, kRevolute, kContinuous, kPrismatic };

const char* JointTypeName(JointType type);

// One URDF joint on the path from base to tip, as written in the URDF.
struct ChainSegment {
  std::string joint_name;
  std::string parent_link;
  std::string child_link;
  JointType type = JointType::kFixed;
  Pose3 T_parent_joint = Pose3::Identity();  // the joint origin (xyz, rpy) in the parent link
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  // in the joint frame; unused when fixed
  double lower = 0.0;  // radians or metres; -inf for continuous
  double upper = 0.0;  // +inf for continuous
};

// A moving joint with the fixed segments before it folded into one transform.
struct ChainJoint {
  std::string name;
  JointType type = JointType::kRevolute;
  // From the previous joint's moved frame (the base link for the first joint) to this joint's
  // frame at zero position; the joint then rotates about or slides along axis.
  Pose3 T_prev_joint = Pose3::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit length
  int axis_index = -1;      // 0, 1, 2 when axis is +-x, +-y, +-z (a faster rotation), else -1
  double axis_sign = 1.0;   // the sign of that coordinate axis
  double lower = 0.0;
  double upper = 0.0;
  // Sampling range: the limits, or [-pi, pi] for continuous joints.
  double sample_lower = 0.0;
  double sample_upper = 0.0;
};

class KinematicChain {
 public:
  const std::string& base_link() const { return base_link_; }
  const std::string& tip_link() const { return tip_link_; }
  int dof() const { return static_cast<int>(joints_.size()); }
  const std::vector<ChainSegment>& segments() const { return segments_; }
  const std::vector<ChainJoint>& joints() const { return joints_; }
  const Pose3& tip_from_tool() const { return tip_from_tool_; }
  // The fixed segments after the last joint followed by the tool offset.
  const Pose3& last_joint_from_tool() const { return last_joint_from_tool_; }

  Eigen::VectorXd LowerLimits() const;
  Eigen::VectorXd UpperLimits() const;
  // The middle of each joint's sampling range (0 for continuous joints).
  Eigen::VectorXd MidLimits() const;

  // The same chain with another tool mounted on the tip.
  KinematicChain WithTool(const Pose3& tip_from_tool) const;

 private:
  friend StatusOr<KinematicChain> ChainFromSegments(std::string base_link, std::vector<ChainSegment> segments,
                                                    const Pose3& tip_from_tool);
  std::string base_link_;
  std::string tip_link_;
  std::vector<ChainSegment> segments_;
  std::vector<ChainJoint> joints_;
  Pose3 tip_from_tool_ = Pose3::Identity();
  Pose3 last_joint_from_tip_ = Pose3::Identity();
  Pose3 last_joint_from_tool_ = Pose3::Identity();
};

// Builds a chain from segments ordered base to tip (each child the next one's parent). Needs at
// least one and at most kMaxChainJoints moving joints, non-zero finite axes, lower <= upper.
StatusOr<KinematicChain> ChainFromSegments(std::string base_link, std::vector<ChainSegment> segments,
                                           const Pose3& tip_from_tool = Pose3::Identity());

// q with every joint clamped into its limits.
Eigen::VectorXd ClampToLimits(const KinematicChain& chain, Eigen::VectorXd q);

// Uniform in each joint's sampling range.
Eigen::VectorXd RandomJointPositions(const KinematicChain& chain, std::mt19937_64& rng);

}  // namespace vscan::robot
