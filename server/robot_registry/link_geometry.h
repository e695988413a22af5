#pragma once
// The geometry of every link of a robot, in link frames, and the link poses for joint positions.
// Links are the URDF's links in name order; their poses follow the whole URDF tree, with the
// chain's joints at the given positions and joints off the chain at zero.

#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "robot/chain.h"
#include "robot/urdf_bundle.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::robot_registry {

// A mesh in metres, the URDF's mesh scale applied, placed in its link: link_point = link_from_shape * mesh_point.
struct LinkShape {
  std::shared_ptr<const TriangleMesh> mesh;
  Pose3 link_from_shape = Pose3::Identity();
};

// How a link hangs from its parent (the URDF tree).
struct LinkJoint {
  int parent = -1;  // link index; -1 for the root
  Pose3 parent_from_joint = Pose3::Identity();
  robot::JointType type = robot::JointType::kFixed;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int chain_joint = -1;  // index in the chain's moving joints; -1 off the chain (held at zero)
};

struct RobotLinks {
  std::vector<std::string> names;  // sorted
  std::vector<LinkJoint> joints;   // one per link
  int base = 0;                    // the chain's base link
  std::vector<std::vector<LinkShape>> visual;     // visual geometry, else the collision geometry
  std::vector<std::vector<LinkShape>> collision;  // collision geometry, else the visual geometry
  std::vector<std::string> warnings;              // geometry that could not be used
  // Link index pairs (lower first) whose contacts are expected: see AllowedLinkContacts.
  std::set<std::pair<size_t, size_t>> allowed_contacts;
};

// Parses a mesh file of the bundle (bytes of bundle_path) into metres; an error becomes a warning.
using LinkMeshImporter = std::function<StatusOr<TriangleMesh>(std::string_view bytes, std::string_view bundle_path)>;

// Boxes, cylinders and spheres are meshed here; mesh files go through import.
StatusOr<RobotLinks> LoadRobotLinks(const robot::UrdfBundle& bundle, const robot::KinematicChain& chain,
                                    const LinkMeshImporter& import);

// base_from_link of every link at q (one value per chain joint; unchecked).
std::vector<Pose3> LinkPoses(const RobotLinks& links, const Eigen::VectorXd& q);

// Instance ids of link geometry in scans: 0x80000000 | slot << 8 | (link index + 1), where slot
// is the first 23 bits of the mount id's hex digits. Object ids count up from 1, so the ranges
// never meet. Links past the 255th have no id (0) and are not drawn.
inline constexpr uint32_t kLinkInstanceIdBit = 0x80000000u;
inline constexpr size_t kMaxVisibleLinks = 255;
uint32_t LinkInstanceIdBase(std::string_view mount_id);
inline uint32_t LinkInstanceId(std::string_view mount_id, size_t link_index) {
  return link_index < kMaxVisibleLinks ? LinkInstanceIdBase(mount_id) + static_cast<uint32_t>(link_index) + 1 : 0;
}

}  // namespace vscan::robot_registry
