#include "robot/urdf_rootless_loops.h"

#include <map>
#include <set>
#include <string>
#include <vector>

#include <tinyxml.h>

namespace vscan::robot {
namespace {

using Children = std::map<std::string, std::vector<std::string>>;

std::string LinkOf(const TiXmlElement& joint, const char* role) {
  const TiXmlElement* element = joint.FirstChildElement(role);
  const char* name = element != nullptr ? element->Attribute("link") : nullptr;
  return name != nullptr ? name : "";
}

// Depth-first search for a back edge, iterative so that a long chain cannot exhaust the stack.
bool HasLoop(const Children& children) {
  enum class Mark { kOpen, kDone };
  std::map<std::string, Mark> marks;
  for (const auto& [start, unused] : children) {
    if (marks.count(start) != 0) continue;
    std::vector<std::pair<std::string, size_t>> stack{{start, 0}};
    marks[start] = Mark::kOpen;
    while (!stack.empty()) {
      auto& [link, next] = stack.back();
      const auto found = children.find(link);
      if (found == children.end() || next == found->second.size()) {
        marks[link] = Mark::kDone;
        stack.pop_back();
        continue;
      }
      const std::string child = found->second[next++];
      const auto mark = marks.find(child);
      if (mark != marks.end() && mark->second == Mark::kOpen) return true;
      if (mark == marks.end()) {
        marks[child] = Mark::kOpen;
        stack.emplace_back(child, 0);
      }
    }
  }
  return false;
}

}  // namespace

Status CheckNoRootlessLoops(const std::string& xml) {
  // The parser urdfdom reads with, called as urdfdom calls it, so that both see the same elements.
  TiXmlDocument document;
  document.Parse(xml.c_str());
  if (document.Error()) return Status::Ok();
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) return Status::Ok();
  std::set<std::string> links;
  for (const auto* link = robot->FirstChildElement("link"); link != nullptr; link = link->NextSiblingElement("link")) {
    if (const char* name = link->Attribute("name"); name != nullptr) links.insert(name);
  }
  std::set<std::string> roots = links;
  std::string unknown;  // a link a joint names that the document lacks
  Children children;
  for (const auto* joint = robot->FirstChildElement("joint"); joint != nullptr;
       joint = joint->NextSiblingElement("joint")) {
    const std::string parent = LinkOf(*joint, "parent");
    const std::string child = LinkOf(*joint, "child");
    for (const std::string& link : {parent, child}) {
      if (unknown.empty() && links.count(link) == 0) unknown = "'" + link + "'";
    }
    children[parent].push_back(child);
    roots.erase(child);
  }
  if ((roots.size() == 1 && unknown.empty()) || !HasLoop(children)) return Status::Ok();
  if (!unknown.empty()) return InvalidArgument("urdf: the joints loop, and one names a link " + unknown + " it lacks");
  return InvalidArgument("urdf: the joints loop, and " + std::to_string(roots.size()) +
                         " links have no parent joint where a tree has exactly one root");
}

}  // namespace vscan::robot
