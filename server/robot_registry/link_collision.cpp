#include "robot_registry/link_collision.h"

#include <algorithm>

namespace vscan::robot_registry {
namespace {

// Links whose pose no chain joint changes.
std::vector<bool> FixedToBase(const RobotLinks& links) {
  const size_t n = links.names.size();
  std::vector<bool> fixed(n, true);
  for (size_t i = 0; i < n; ++i) {
    // At most one step per link, so parents that loop (refused at upload) cannot hold the walk.
    int at = static_cast<int>(i);
    for (size_t steps = 0; at >= 0 && steps < n; ++steps) {
      const LinkJoint& joint = links.joints[static_cast<size_t>(at)];
      if (joint.chain_joint >= 0) {
        fixed[i] = false;
        break;
      }
      at = joint.parent;
    }
  }
  return fixed;
}

struct LinkWorld {
  std::unique_ptr<collision::CollisionWorld> world;
  std::vector<int> link_of_body;  // -1 for obstacles
  std::vector<size_t> obstacle_of_body;
};

StatusOr<LinkWorld> BuildWorld(const RobotLinks& links, const Pose3& world_from_base, const Eigen::VectorXd& q,
                               std::span<const Obstacle> obstacles,
                               const std::shared_ptr<collision::ShapeCache>& shapes) {
  LinkWorld out;
  out.world = std::make_unique<collision::CollisionWorld>(shapes);
  const std::vector<Pose3> base_from_link = LinkPoses(links, q);
  const std::vector<bool> fixed = FixedToBase(links);
  std::vector<size_t> link_bodies;
  for (size_t i = 0; i < links.names.size(); ++i) {
    if (links.collision[i].empty()) continue;
    collision::Body body;
    body.kind = collision::BodyKind::kLink;
    for (const LinkShape& shape : links.collision[i]) {
      body.meshes.push_back({shape.mesh, world_from_base * base_from_link[i] * shape.link_from_shape});
    }
    ASSIGN_OR_RETURN(const size_t index, out.world->AddBody(body));
    out.link_of_body.resize(index + 1, -1);
    out.link_of_body[index] = static_cast<int>(i);
    link_bodies.push_back(index);
  }
  for (size_t o = 0; o < obstacles.size(); ++o) {
    if (obstacles[o].meshes.empty()) continue;
    ASSIGN_OR_RETURN(const size_t index, out.world->AddBody({collision::BodyKind::kObject, obstacles[o].meshes}));
    out.link_of_body.resize(index + 1, -1);
    out.obstacle_of_body.resize(index + 1, 0);
    out.obstacle_of_body[index] = o;
    for (size_t body : link_bodies) {
      if (fixed[static_cast<size_t>(out.link_of_body[body])]) out.world->IgnorePair(body, index);
    }
  }
  return out;
}

}  // namespace

std::set<std::pair<size_t, size_t>> AllowedLinkContacts(const RobotLinks& links,
                                                        const std::shared_ptr<collision::ShapeCache>& shapes) {
  std::set<std::pair<size_t, size_t>> allowed;
  for (size_t i = 0; i < links.joints.size(); ++i) {
    if (const int parent = links.joints[i].parent; parent >= 0) {
      allowed.emplace(std::min<size_t>(i, static_cast<size_t>(parent)), std::max<size_t>(i, static_cast<size_t>(parent)));
    }
  }
  auto world = BuildWorld(links, Pose3::Identity(), Eigen::VectorXd::Zero(0), {}, shapes);
  if (!world.ok()) return allowed;
  for (const collision::Contact& contact : world->world->AllContacts()) {
    const auto a = static_cast<size_t>(world->link_of_body[contact.first]);
    const auto b = static_cast<size_t>(world->link_of_body[contact.second]);
    allowed.emplace(std::min(a, b), std::max(a, b));
  }
  return allowed;
}

StatusOr<std::optional<std::string>> FindLinkContact(const RobotLinks& links,
                                                     const std::set<std::pair<size_t, size_t>>& allowed,
                                                     const Pose3& world_from_base, const Eigen::VectorXd& q,
                                                     std::span<const Obstacle> obstacles,
                                                     const std::shared_ptr<collision::ShapeCache>& shapes) {
  ASSIGN_OR_RETURN(LinkWorld world, BuildWorld(links, world_from_base, q, obstacles, shapes));
  for (size_t a = 0; a < world.link_of_body.size(); ++a) {
    for (size_t b = a + 1; b < world.link_of_body.size(); ++b) {
      const int la = world.link_of_body[a], lb = world.link_of_body[b];
      if (la >= 0 && lb >= 0 && allowed.contains({static_cast<size_t>(la), static_cast<size_t>(lb)})) {
        world.world->IgnorePair(a, b);
      }
    }
  }
  // Contacts with obstacles say more about a configuration than self-contacts: report them first.
  const std::vector<collision::Contact> contacts = world.world->AllContacts();
  if (contacts.empty()) return std::optional<std::string>();
  auto contact = std::find_if(contacts.begin(), contacts.end(),
                              [&](const collision::Contact& c) { return world.link_of_body[c.second] < 0; });
  if (contact == contacts.end()) contact = contacts.begin();
  const std::string link = "link '" + links.names[static_cast<size_t>(world.link_of_body[contact->first])] + "'";
  const int other = world.link_of_body[contact->second];
  if (other >= 0) return std::optional<std::string>(link + " touches link '" + links.names[static_cast<size_t>(other)] + "'");
  return std::optional<std::string>(link + " touches " + obstacles[world.obstacle_of_body[contact->second]].description);
}

}  // namespace vscan::robot_registry
