#include "robot/chain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace vscan::robot {
namespace {

constexpr double kAxisTolerance = 1e-12;

std::string SegmentField(size_t i, const ChainSegment& s) {
  return "chain.segments[" + std::to_string(i) + "] (joint '" + s.joint_name + "')";
}

Status CheckSegment(size_t i, const ChainSegment& s) {
  if (!s.T_parent_joint.matrix().allFinite()) return InvalidArgument(SegmentField(i, s) + ": origin is not finite");
  if (s.type == JointType::kFixed) return Status::Ok();
  const double norm = s.axis.norm();
  if (!std::isfinite(norm) || norm < 1e-9) return InvalidArgument(SegmentField(i, s) + ": axis must be a non-zero vector");
  if (s.type == JointType::kContinuous) return Status::Ok();
  if (!std::isfinite(s.lower) || !std::isfinite(s.upper) || s.lower > s.upper) {
    return InvalidArgument(SegmentField(i, s) + ": limits [" + std::to_string(s.lower) + ", " +
                           std::to_string(s.upper) + "] must be finite with lower <= upper");
  }
  return Status::Ok();
}

ChainJoint MakeJoint(const ChainSegment& s, const Pose3& T_prev_joint) {
  ChainJoint j;
  j.name = s.joint_name;
  j.type = s.type;
  j.T_prev_joint = T_prev_joint;
  j.axis = s.axis.normalized();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(std::abs(j.axis[k]) - 1.0) < kAxisTolerance) {
      j.axis_index = k;
      j.axis_sign = j.axis[k] > 0 ? 1.0 : -1.0;
      j.axis = Eigen::Vector3d::Unit(k) * j.axis_sign;
    }
  }
  if (s.type == JointType::kContinuous) {
    j.lower = -std::numeric_limits<double>::infinity();
    j.upper = std::numeric_limits<double>::infinity();
    j.sample_lower = -std::numbers::pi;
    j.sample_upper = std::numbers::pi;
  } else {
    j.lower = j.sample_lower = s.lower;
    j.upper = j.sample_upper = s.upper;
  }
  return j;
}

}  // namespace

const char* JointTypeName(JointType type) {
  switch (type) {
    case JointType::kFixed: return "fixed";
    case JointType::kRevolute: return "revolute";
    case JointType::kContinuous: return "continuous";
    case JointType::kPrismatic: return "prismatic";
  }
  return "unknown";
}

StatusOr<KinematicChain> ChainFromSegments(std::string base_link, std::vector<ChainSegment> segments,
                                           const Pose3& tip_from_tool) {
  KinematicChain chain;
  Pose3 pending = Pose3::Identity();  // fixed transforms since the last moving joint
  std::string parent = base_link;
  for (size_t i = 0; i < segments.size(); ++i) {
    const ChainSegment& s = segments[i];
    if (s.parent_link != parent) {
      return InvalidArgument(SegmentField(i, s) + ": parent '" + s.parent_link + "' does not continue the chain at '" +
                             parent + "'");
    }
    RETURN_IF_ERROR(CheckSegment(i, s));
    parent = s.child_link;
    pending = pending * s.T_parent_joint;
    if (s.type == JointType::kFixed) continue;
    chain.joints_.push_back(MakeJoint(s, pending));
    pending = Pose3::Identity();
  }
  if (chain.joints_.empty()) return InvalidArgument("chain: no moving joint between '" + base_link + "' and '" + parent + "'");
  if (chain.dof() > kMaxChainJoints) {
    return InvalidArgument("chain: " + std::to_string(chain.dof()) + " moving joints exceed the limit of " +
                           std::to_string(kMaxChainJoints));
  }
  if (!tip_from_tool.matrix().allFinite()) return InvalidArgument("tip_from_tool: not finite");
  chain.base_link_ = std::move(base_link);
  chain.tip_link_ = parent;
  chain.segments_ = std::move(segments);
  chain.last_joint_from_tip_ = pending;
  return chain.WithTool(tip_from_tool);
}

KinematicChain KinematicChain::WithTool(const Pose3& tip_from_tool) const {
  KinematicChain out = *this;
  out.tip_from_tool_ = tip_from_tool;
  out.last_joint_from_tool_ = last_joint_from_tip_ * tip_from_tool;
  return out;
}

Eigen::VectorXd KinematicChain::LowerLimits() const {
  Eigen::VectorXd v(dof());
  for (int i = 0; i < dof(); ++i) v[i] = joints_[i].lower;
  return v;
}

Eigen::VectorXd KinematicChain::UpperLimits() const {
  Eigen::VectorXd v(dof());
  for (int i = 0; i < dof(); ++i) v[i] = joints_[i].upper;
  return v;
}

Eigen::VectorXd KinematicChain::MidLimits() const {
  Eigen::VectorXd v(dof());
  for (int i = 0; i < dof(); ++i) v[i] = 0.5 * (joints_[i].sample_lower + joints_[i].sample_upper);
  return v;
}

Eigen::VectorXd ClampToLimits(const KinematicChain& chain, Eigen::VectorXd q) {
  for (int i = 0; i < chain.dof() && i < q.size(); ++i) {
    q[i] = std::clamp(q[i], chain.joints()[i].lower, chain.joints()[i].upper);
  }
  return q;
}

Eigen::VectorXd RandomJointPositions(const KinematicChain& chain, std::mt19937_64& rng) {
  Eigen::VectorXd q(chain.dof());
  for (int i = 0; i < chain.dof(); ++i) {
    const ChainJoint& j = chain.joints()[i];
    q[i] = std::uniform_real_distribution<double>(j.sample_lower, j.sample_upper)(rng);
  }
  return q;
}

}  // namespace vscan::robot
