#include "robot/urdf_tree.h"

#include <map>
#include <string>
#include <vector>

#include <urdf_model/model.h>

namespace vscan::robot {
namespace {

using ChildJoints = std::map<std::string, std::vector<const urdf::Joint*>>;

std::string JointField(const std::string& name) { return "joints['" + name + "']"; }

// Depth-first from every link, following joints from parent to child; each link is entered once,
// so the walk is bounded by the number of joints.
Status FindCycle(const urdf::ModelInterface& model, const ChildJoints& children) {
  enum class State { kNew, kOnPath, kDone };
  std::map<std::string, State> state;
  for (const auto& [name, link] : model.links_) state[name] = State::kNew;
  struct Frame {
    std::string link;
    size_t next = 0;  // index of the next child joint to follow
  };
  for (const auto& [start, unused] : model.links_) {
    if (state[start] != State::kNew) continue;
    std::vector<Frame> path = {{start}};
    std::vector<const urdf::Joint*> joints;  // joints[k] leads from path[k] to path[k + 1]
    state[start] = State::kOnPath;
    while (!path.empty()) {
      Frame& top = path.back();
      const auto found = children.find(top.link);
      if (found == children.end() || top.next == found->second.size()) {
        state[top.link] = State::kDone;
        path.pop_back();
        if (!joints.empty()) joints.pop_back();
        continue;
      }
      const urdf::Joint* joint = found->second[top.next++];
      const std::string& child = joint->child_link_name;
      if (state[child] == State::kOnPath) {
        size_t from = 0;
        while (path[from].link != child) ++from;
        std::string names;
        for (size_t k = from; k < joints.size(); ++k) names += joints[k]->name + " -> ";
        const std::string first = from < joints.size() ? joints[from]->name : joint->name;
        return InvalidArgument("joints: cycle through joints " + names + joint->name + " -> " + first);
      }
      if (state[child] == State::kDone) continue;  // a second parent; reported after the cycles
      state[child] = State::kOnPath;
      joints.push_back(joint);
      path.push_back({child});
    }
  }
  return Status::Ok();
}

}  // namespace

Status CheckUrdfTree(const urdf::ModelInterface& model) {
  ChildJoints children;
  for (const auto& [name, joint] : model.joints_) {
    if (joint->parent_link_name == joint->child_link_name) {
      return InvalidArgument(JointField(name) + ": parent and child are the same link '" + joint->child_link_name +
                             "'");
    }
    // joints_ is a std::map: children in joint-name order, so the message is deterministic.
    children[joint->parent_link_name].push_back(joint.get());
  }
  RETURN_IF_ERROR(FindCycle(model, children));
  std::map<std::string, std::string> parent_joint;
  for (const auto& [name, joint] : model.joints_) {
    const auto [it, inserted] = parent_joint.emplace(joint->child_link_name, name);
    if (!inserted) {
      return InvalidArgument("links['" + joint->child_link_name + "']: child of two joints, '" + it->second +
                             "' and '" + name + "' (a URDF is a tree: one parent joint per link)");
    }
  }
  return Status::Ok();
}

}  // namespace vscan::robot
