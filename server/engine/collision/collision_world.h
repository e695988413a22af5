#pragma once
// Contact tests between placed meshes with Bullet (kept inside the .cpp files).
// Scene objects are static concave triangle meshes (BVH); robot links are convex hulls of their
// meshes. Only link-object and link-link pairs are tested; pairs can be excluded.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::collision {

// world_point = world_from_mesh * (scale * mesh_point), scale per axis.
struct PlacedMesh {
  std::shared_ptr<const TriangleMesh> mesh;
  Pose3 world_from_mesh = Pose3::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

enum class BodyKind { kObject, kLink };

struct Body {
  BodyKind kind = BodyKind::kObject;
  std::vector<PlacedMesh> meshes;
};

// Bullet shapes built from meshes, kept for reuse across worlds (a BVH over a large scan target
// costs far more than a contact test). Thread-safe; holds at most capacity meshes' shapes.
class ShapeCache {
 public:
  explicit ShapeCache(size_t capacity = 256);
  ~ShapeCache();
  ShapeCache(const ShapeCache&) = delete;
  ShapeCache& operator=(const ShapeCache&) = delete;

  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

struct Contact {
  size_t first = 0;   // body index; a link when the pair is link-object, the lower one when link-link
  size_t second = 0;  // body index
  double distance = 0.0;  // metres; negative when the shapes overlap
};

class CollisionWorld {
 public:
  // Contacts count when the shapes are closer than touch_distance (0: touching or overlapping).
  explicit CollisionWorld(std::shared_ptr<ShapeCache> shapes, double touch_distance = 0.0);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  // Returns the body's index. INVALID_ARGUMENT for a mesh that is missing, empty or not finite.
  StatusOr<size_t> AddBody(const Body& body);
  // Pairs never reported (order does not matter).
  void IgnorePair(size_t a, size_t b);

  // Every contact (one per body pair, the deepest), ordered by (first, second).
  std::vector<Contact> AllContacts();
  std::optional<Contact> FirstContact();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::collision
