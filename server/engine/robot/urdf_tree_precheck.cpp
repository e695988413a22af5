#include "robot/urdf_tree_precheck.h"

#include <memory>

#include <tinyxml.h>
#include <urdf_model/model.h>

#include "robot/urdf_tree.h"

namespace vscan::robot {
namespace {

std::string Attribute(const TiXmlElement* element, const char* name) {
  const char* value = element != nullptr ? element->Attribute(name) : nullptr;
  return value != nullptr ? value : "";
}

}  // namespace

Status CheckUrdfTreeBeforeParse(const std::string& xml) {
  // The parser urdfdom reads with, called as urdfdom calls it, so that both see the same elements.
  TiXmlDocument document;
  document.Parse(xml.c_str());
  if (document.Error()) return Status::Ok();
  const TiXmlElement* robot = document.FirstChildElement("robot");
  if (robot == nullptr) return Status::Ok();
  // Only the names CheckUrdfTree reads: the links, and each joint's parent and child.
  urdf::ModelInterface graph;
  for (const auto* link = robot->FirstChildElement("link"); link != nullptr; link = link->NextSiblingElement("link")) {
    auto node = std::make_shared<urdf::Link>();
    node->name = Attribute(link, "name");
    graph.links_[node->name] = node;
  }
  for (const auto* joint = robot->FirstChildElement("joint"); joint != nullptr;
       joint = joint->NextSiblingElement("joint")) {
    auto edge = std::make_shared<urdf::Joint>();
    edge->name = Attribute(joint, "name");
    edge->parent_link_name = Attribute(joint->FirstChildElement("parent"), "link");
    edge->child_link_name = Attribute(joint->FirstChildElement("child"), "link");
    graph.joints_[edge->name] = edge;
  }
  return CheckUrdfTree(graph);
}

}  // namespace vscan::robot
