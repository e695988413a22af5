#pragma once
// Whether a robot's links touch obstacles or each other, on the collision engine. Link geometry
// is the URDF's collision geometry (else its visual geometry), tested as convex hulls; obstacles
// are triangle meshes. Links that never move with the chain (the base and what is fixed to it)
// stand on their support and are not tested against obstacles.

#include <cstddef>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "collision/collision_world.h"
#include "robot_registry/link_geometry.h"

namespace vscan::robot_registry {

struct Obstacle {
  std::string description;  // e.g. "object 'obj_...' (bunny)"
  std::vector<collision::PlacedMesh> meshes;
};

// Link pairs never reported: parent and child, and pairs already touching at zero joint positions.
std::set<std::pair<size_t, size_t>> AllowedLinkContacts(const RobotLinks& links,
                                                        const std::shared_ptr<collision::ShapeCache>& shapes);

// The first contact at q, as "link 'X' touches <obstacle description>" or "link 'X' touches link
// 'Y'"; empty when clear.
StatusOr<std::optional<std::string>> FindLinkContact(const RobotLinks& links,
                                                     const std::set<std::pair<size_t, size_t>>& allowed,
                                                     const Pose3& world_from_base, const Eigen::VectorXd& q,
                                                     std::span<const Obstacle> obstacles,
                                                     const std::shared_ptr<collision::ShapeCache>& shapes);

}  // namespace vscan::robot_registry
