#include "collision/collision_world.h"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/CollisionShapes/btScaledBvhTriangleMeshShape.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <tuple>

namespace vscan::collision {
namespace {

// Small but non-zero: GJK needs a margin, and it widens every shape by this much.
constexpr btScalar kHullMargin = btScalar(1e-4);

btTransform ToBullet(const Pose3& pose) {
  const Eigen::Matrix3d r = pose.linear();
  const Eigen::Vector3d t = pose.translation();
  btMatrix3x3 basis(btScalar(r(0, 0)), btScalar(r(0, 1)), btScalar(r(0, 2)), btScalar(r(1, 0)), btScalar(r(1, 1)),
                    btScalar(r(1, 2)), btScalar(r(2, 0)), btScalar(r(2, 1)), btScalar(r(2, 2)));
  return btTransform(basis, btVector3(btScalar(t.x()), btScalar(t.y()), btScalar(t.z())));
}

// A static BVH over a mesh's triangles; Bullet reads the mesh's own arrays, which it keeps alive.
struct BvhShape {
  std::shared_ptr<const TriangleMesh> mesh;
  std::unique_ptr<btTriangleIndexVertexArray> arrays;
  std::unique_ptr<btBvhTriangleMeshShape> shape;
};

std::shared_ptr<BvhShape> MakeBvh(std::shared_ptr<const TriangleMesh> mesh) {
  auto out = std::make_shared<BvhShape>();
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
  static_assert(sizeof(std::array<uint32_t, 3>) == 3 * sizeof(uint32_t));
  btIndexedMesh indexed;
  indexed.m_numTriangles = static_cast<int>(mesh->triangles.size());
  indexed.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(mesh->triangles.data());
  indexed.m_triangleIndexStride = 3 * sizeof(uint32_t);
  indexed.m_numVertices = static_cast<int>(mesh->vertices.size());
  indexed.m_vertexBase = reinterpret_cast<const unsigned char*>(mesh->vertices.data());
  indexed.m_vertexStride = 3 * sizeof(float);
  indexed.m_indexType = PHY_INTEGER;
  indexed.m_vertexType = PHY_FLOAT;
  out->arrays = std::make_unique<btTriangleIndexVertexArray>();
  out->arrays->addIndexedMesh(indexed, PHY_INTEGER);
  out->shape = std::make_unique<btBvhTriangleMeshShape>(out->arrays.get(), true, true);
  out->shape->setMargin(0);
  out->mesh = std::move(mesh);
  return out;
}

// The exact convex hull of the scaled vertices, reduced to its own vertices.
std::shared_ptr<btConvexHullShape> MakeHull(const TriangleMesh& mesh, const Eigen::Vector3d& scale) {
  std::vector<float> coords;
  coords.reserve(mesh.vertices.size() * 3);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) coords.push_back(static_cast<float>(v[k] * scale[k]));
  }
  btConvexHullComputer computer;
  computer.compute(coords.data(), 3 * sizeof(float), static_cast<int>(mesh.vertices.size()), 0, 0);
  auto hull = std::make_shared<btConvexHullShape>();
  if (computer.vertices.size() >= 4) {
    for (int i = 0; i < computer.vertices.size(); ++i) hull->addPoint(computer.vertices[i], false);
  } else {  // flat or degenerate: keep every point
    for (size_t i = 0; i + 2 < coords.size(); i += 3) {
      hull->addPoint(btVector3(coords[i], coords[i + 1], coords[i + 2]), false);
    }
  }
  hull->recalcLocalAabb();
  hull->setMargin(kHullMargin);
  return hull;
}

Status CheckMesh(const PlacedMesh& placed, size_t body, size_t index) {
  const std::string field = "bodies[" + std::to_string(body) + "].meshes[" + std::to_string(index) + "]";
  if (placed.mesh == nullptr || placed.mesh->empty()) return InvalidArgument(field + ".mesh: missing or empty");
  if (!placed.world_from_mesh.matrix().allFinite()) return InvalidArgument(field + ".world_from_mesh: not finite");
  if (!placed.scale.allFinite() || (placed.scale.array() <= 0).any()) {
    return InvalidArgument(field + ".scale: must be finite and positive");
  }
  for (const Eigen::Vector3f& v : placed.mesh->vertices) {
    if (!v.allFinite()) return InvalidArgument(field + ".mesh: NaN or infinite vertex");
  }
  return Status::Ok();
}

}  // namespace

struct ShapeCache::Impl {
  explicit Impl(size_t capacity) : capacity(capacity) {}

  std::shared_ptr<BvhShape> Bvh(const std::shared_ptr<const TriangleMesh>& mesh) {
    std::lock_guard lock(mutex);
    Entry& entry = Find({mesh.get(), 0, 0, 0}, mesh);  // a zero scale marks the BVH
    if (!entry.bvh) entry.bvh = MakeBvh(mesh);
    return entry.bvh;
  }

  std::shared_ptr<btConvexHullShape> Hull(const std::shared_ptr<const TriangleMesh>& mesh,
                                          const Eigen::Vector3d& scale) {
    std::lock_guard lock(mutex);
    Entry& entry = Find({mesh.get(), scale.x(), scale.y(), scale.z()}, mesh);
    if (!entry.hull) entry.hull = MakeHull(*mesh, scale);
    return entry.hull;
  }

 private:
  using Key = std::tuple<const TriangleMesh*, double, double, double>;
  struct Entry {
    // Holding the mesh keeps its address from being reused for another mesh while cached.
    std::shared_ptr<const TriangleMesh> mesh;
    std::shared_ptr<BvhShape> bvh;
    std::shared_ptr<btConvexHullShape> hull;
    uint64_t last_use = 0;
  };

  Entry& Find(const Key& key, const std::shared_ptr<const TriangleMesh>& mesh) {
    auto it = entries.find(key);
    if (it == entries.end()) {
      if (entries.size() >= capacity) {
        auto oldest = std::min_element(entries.begin(), entries.end(), [](const auto& x, const auto& y) {
          return x.second.last_use < y.second.last_use;
        });
        entries.erase(oldest);
      }
      it = entries.emplace(key, Entry{mesh, nullptr, nullptr, 0}).first;
    }
    it->second.last_use = ++clock;
    return it->second;
  }

  size_t capacity;
  std::mutex mutex;
  uint64_t clock = 0;
  std::map<Key, Entry> entries;
};

ShapeCache::ShapeCache(size_t capacity) : impl_(std::make_unique<Impl>(capacity)) {}
ShapeCache::~ShapeCache() = default;

struct CollisionWorld::Impl {
  Impl(std::shared_ptr<ShapeCache> cache, double touch)
      : shapes(std::move(cache)), touch_distance(touch), dispatcher(&configuration),
        world(&dispatcher, &broadphase, &configuration) {}

  ~Impl() {
    for (auto& object : objects) world.removeCollisionObject(object.get());
  }

  std::shared_ptr<ShapeCache> shapes;
  double touch_distance;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher;
  btDbvtBroadphase broadphase;
  btCollisionWorld world;

  std::vector<BodyKind> kinds;
  std::set<std::pair<size_t, size_t>> ignored;
  // Shapes in use: shared with the cache, or owned here (the scaling wrappers).
  std::vector<std::shared_ptr<void>> held;
  std::vector<std::unique_ptr<btCollisionShape>> owned;
  std::vector<std::unique_ptr<btCollisionObject>> objects;
};

CollisionWorld::CollisionWorld(std::shared_ptr<ShapeCache> shapes, double touch_distance)
    : impl_(std::make_unique<Impl>(shapes ? std::move(shapes) : std::make_shared<ShapeCache>(), touch_distance)) {}
CollisionWorld::~CollisionWorld() = default;

StatusOr<size_t> CollisionWorld::AddBody(const Body& body) {
  Impl& w = *impl_;
  const size_t index = w.kinds.size();
  for (size_t i = 0; i < body.meshes.size(); ++i) RETURN_IF_ERROR(CheckMesh(body.meshes[i], index, i));
  w.kinds.push_back(body.kind);
  for (const PlacedMesh& placed : body.meshes) {
    btCollisionShape* shape = nullptr;
    if (body.kind == BodyKind::kObject) {
      auto bvh = w.shapes->impl().Bvh(placed.mesh);
      const btVector3 scale(btScalar(placed.scale.x()), btScalar(placed.scale.y()), btScalar(placed.scale.z()));
      w.owned.push_back(std::make_unique<btScaledBvhTriangleMeshShape>(bvh->shape.get(), scale));
      shape = w.owned.back().get();
      w.held.push_back(std::move(bvh));
    } else {
      auto hull = w.shapes->impl().Hull(placed.mesh, placed.scale);
      shape = hull.get();
      w.held.push_back(std::move(hull));
    }
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shape);
    object->setWorldTransform(ToBullet(placed.world_from_mesh));
    object->setUserIndex(static_cast<int>(index));
    // Objects never meet objects: only links look for contacts.
    if (body.kind == BodyKind::kObject) {
      object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
      w.world.addCollisionObject(object.get(), btBroadphaseProxy::StaticFilter,
                                 btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
    } else {
      w.world.addCollisionObject(object.get(), btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    }
    w.objects.push_back(std::move(object));
  }
  return index;
}

void CollisionWorld::IgnorePair(size_t a, size_t b) { impl_->ignored.emplace(std::min(a, b), std::max(a, b)); }

std::vector<Contact> CollisionWorld::AllContacts() {
  Impl& w = *impl_;
  w.world.performDiscreteCollisionDetection();
  std::map<std::pair<size_t, size_t>, double> deepest;
  const int manifolds = w.dispatcher.getNumManifolds();
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* manifold = w.dispatcher.getManifoldByIndexInternal(m);
    const auto a = static_cast<size_t>(manifold->getBody0()->getUserIndex());
    const auto b = static_cast<size_t>(manifold->getBody1()->getUserIndex());
    if (a == b || w.ignored.contains({std::min(a, b), std::max(a, b)})) continue;
    if (w.kinds[a] == BodyKind::kObject && w.kinds[b] == BodyKind::kObject) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      nearest = std::min(nearest, static_cast<double>(manifold->getContactPoint(p).getDistance()));
    }
    if (!(nearest <= w.touch_distance)) continue;
    // A link comes first in a link-object pair; otherwise the lower index does.
    std::pair<size_t, size_t> key{std::min(a, b), std::max(a, b)};
    if (w.kinds[key.first] == BodyKind::kObject) std::swap(key.first, key.second);
    auto [it, inserted] = deepest.emplace(key, nearest);
    if (!inserted) it->second = std::min(it->second, nearest);
  }
  std::vector<Contact> out;
  for (const auto& [pair, distance] : deepest) out.push_back({pair.first, pair.second, distance});
  return out;
}

std::optional<Contact> CollisionWorld::FirstContact() {
  std::vector<Contact> all = AllContacts();
  if (all.empty()) return std::nullopt;
  return all.front();
}

}  // namespace vscan::collision
