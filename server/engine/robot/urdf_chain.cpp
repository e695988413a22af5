#include "robot/urdf_chain.h"

#include <algorithm>
#include <limits>
#include <set>

#include <urdf_model/model.h>

namespace vscan::robot {
namespace {

using LinkPtr = urdf::LinkConstSharedPtr;

StatusOr<LinkPtr> FindLink(const urdf::ModelInterface& model, const std::string& name, const char* field) {
  LinkPtr link = model.getLink(name);
  if (link == nullptr) return NotFound(std::string(field), "no link '" + name + "'");
  return link;
}

// The deepest links below base, by joint count. Each link is entered once: a link reached a
// second time (a cycle, or two parent joints) is an error, not an endless walk.
StatusOr<std::vector<LinkPtr>> DeepestLinks(const LinkPtr& base) {
  std::vector<LinkPtr> deepest;
  int best_depth = -1;
  std::set<const urdf::Link*> seen = {base.get()};
  std::vector<std::pair<LinkPtr, int>> stack = {{base, 0}};
  while (!stack.empty()) {
    auto [link, depth] = stack.back();
    stack.pop_back();
    if (depth > best_depth) {
      best_depth = depth;
      deepest.clear();
    }
    if (depth == best_depth) deepest.push_back(link);
    for (const auto& child : link->child_links) {
      if (!seen.insert(child.get()).second) {
        return InvalidArgument("joints: link '" + child->name + "' is reached twice from '" + base->name +
                               "' (the joints are not a tree)");
      }
      stack.emplace_back(child, depth + 1);
    }
  }
  return deepest;
}

StatusOr<LinkPtr> DefaultTip(const LinkPtr& base) {
  ASSIGN_OR_RETURN(std::vector<LinkPtr> deepest, DeepestLinks(base));
  if (deepest.size() == 1) return deepest.front();
  std::sort(deepest.begin(), deepest.end(), [](const LinkPtr& a, const LinkPtr& b) { return a->name < b->name; });
  std::string names;
  for (const LinkPtr& link : deepest) names += (names.empty() ? "'" : ", '") + link->name + "'";
  return InvalidArgument("tip_link", "ambiguous, the deepest links below '" + base->name + "' are " + names +
                         "; name one as tip_link");
}

Pose3 ToPose(const urdf::Pose& p) {
  double x = 0, y = 0, z = 0, w = 1;
  p.rotation.getQuaternion(x, y, z, w);
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  pose.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return pose;
}

StatusOr<ChainSegment> ToSegment(const urdf::Joint& joint) {
  ChainSegment s;
  s.joint_name = joint.name;
  s.parent_link = joint.parent_link_name;
  s.child_link = joint.child_link_name;
  s.T_parent_joint = ToPose(joint.parent_to_joint_origin_transform);
  s.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z);
  const std::string field = "joints['" + joint.name + "']";
  if (joint.mimic != nullptr && joint.type != urdf::Joint::FIXED) {
    return InvalidArgument(field, "mimic joints inside the chain are not supported");
  }
  switch (joint.type) {
    case urdf::Joint::FIXED: s.type = JointType::kFixed; return s;
    case urdf::Joint::CONTINUOUS:
      s.type = JointType::kContinuous;
      s.lower = -std::numeric_limits<double>::infinity();
      s.upper = std::numeric_limits<double>::infinity();
      return s;
    case urdf::Joint::REVOLUTE: s.type = JointType::kRevolute; break;
    case urdf::Joint::PRISMATIC: s.type = JointType::kPrismatic; break;
    default: return InvalidArgument(field, "floating, planar and unknown joints are not supported in a chain");
  }
  if (joint.limits == nullptr) return InvalidArgument(field, std::string("a ") + JointTypeName(s.type) + " joint needs limits");
  s.lower = joint.limits->lower;
  s.upper = joint.limits->upper;
  return s;
}

}  // namespace

StatusOr<KinematicChain> BuildChain(const urdf::ModelInterface& model, const ChainSpec& spec) {
  LinkPtr root = model.getRoot();
  if (root == nullptr) return InvalidArgument("urdf", "model has no root link");
  LinkPtr base = root;
  if (!spec.base_link.empty()) {
    ASSIGN_OR_RETURN(base, FindLink(model, spec.base_link, "base_link"));
  }
  LinkPtr tip;
  if (spec.tip_link.empty()) {
    ASSIGN_OR_RETURN(tip, DefaultTip(base));
  } else {
    ASSIGN_OR_RETURN(tip, FindLink(model, spec.tip_link, "tip_link"));
  }
  std::vector<ChainSegment> segments;
  std::set<const urdf::Link*> seen;
  for (LinkPtr link = tip; link != base; link = link->getParent()) {
    if (link->parent_joint == nullptr || link->getParent() == nullptr) {
      return InvalidArgument("tip_link", "'" + tip->name + "' is not below base_link '" + base->name + "'");
    }
    // urdfdom's parent pointers can loop when the joints do.
    if (!seen.insert(link.get()).second) {
      return InvalidArgument("tip_link: the links above '" + tip->name + "' loop through '" + link->name +
                             "' (the joints are not a tree)");
    }
    ASSIGN_OR_RETURN(ChainSegment segment, ToSegment(*link->parent_joint));
    segments.push_back(std::move(segment));
  }
  std::reverse(segments.begin(), segments.end());
  return ChainFromSegments(base->name, std::move(segments), spec.tip_from_tool);
}

}  // namespace vscan::robot
