#include "physics/face_axis_contacts.h"

#include <BulletCollision/CollisionShapes/btConvexPolyhedron.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <new>
#include <vector>

namespace vscan::physics {
namespace {

const btConvexPolyhedron* Polyhedron(const btCollisionShape& shape) {
  if (!shape.isPolyhedral()) return nullptr;
  return static_cast<const btPolyhedralConvexShape&>(shape).getConvexPolyhedron();
}

// How far B's vertices stay outside each of A's face planes (negative: how deep the deepest lies
// inside), over the faces from `first` on; stops at a positive one (a plane that separates the
// hulls). Raises `best` to the greatest found and sets `best_face` to its face. A face is skipped
// where even B's centre, inside B, lies no farther outside than `best`.
void FaceQuery(const btConvexPolyhedron& a, const btConvexPolyhedron& b, const btTransform& world_from_a,
               const btTransform& world_from_b, int first, btScalar& best, int& best_face) {
  const btTransform a_from_b = world_from_a.inverse() * world_from_b;
  const btVector3 centre = a_from_b * b.m_localCenter;
  const int faces = a.m_faces.size();
  for (int k = 0; k < faces && best <= 0; ++k) {
    const int f = (first + k) % faces;
    const btScalar* plane = a.m_faces[f].m_plane;  // n . x + d = 0, n outward, A's frame
    const btVector3 n(plane[0], plane[1], plane[2]);
    if (n.dot(centre) + plane[3] <= best) continue;
    // B's vertices against the plane, in B's frame.
    const btVector3 n_in_b = n * a_from_b.getBasis();
    const btScalar offset = n.dot(a_from_b.getOrigin()) + plane[3];
    btScalar nearest = std::numeric_limits<btScalar>::max();
    for (int v = 0; v < b.m_vertices.size(); ++v) nearest = std::min(nearest, n_in_b.dot(b.m_vertices[v]));
    if (nearest + offset > best) best = nearest + offset, best_face = f;
  }
}

class FaceAxisAlgorithm final : public btActivatingCollisionAlgorithm {
 public:
  FaceAxisAlgorithm(const btCollisionAlgorithmConstructionInfo& info, const btCollisionObjectWrapper* a,
                    const btCollisionObjectWrapper* b)
      : btActivatingCollisionAlgorithm(info, a, b), manifold_(info.m_manifold) {}

  ~FaceAxisAlgorithm() override {
    if (own_manifold_ && manifold_ != nullptr) m_dispatcher->releaseManifold(manifold_);
  }

  void processCollision(const btCollisionObjectWrapper* a, const btCollisionObjectWrapper* b, const btDispatcherInfo&,
                        btManifoldResult* result) override {
    if (manifold_ == nullptr) {
      manifold_ = m_dispatcher->getNewManifold(a->getCollisionObject(), b->getCollisionObject());
      own_manifold_ = true;
    }
    result->setPersistentManifold(manifold_);
    const btConvexPolyhedron& hull_a = *Polyhedron(*a->getCollisionShape());
    const btConvexPolyhedron& hull_b = *Polyhedron(*b->getCollisionShape());
    const btTransform& world_from_a = a->getWorldTransform();
    const btTransform& world_from_b = b->getWorldTransform();
    // Separation along each face normal of either hull; the greatest is the least overlap (or a
    // gap, and then no contact), as in Bullet's test without the edge pairs. Last step's face
    // first, which usually settles it at once (a resting pair keeps its face).
    btScalar separation = -std::numeric_limits<btScalar>::max();
    int face = -1;
    bool on_b = false;
    const auto query = [&](bool b_faces, int first) {
      int found = -1;
      if (b_faces) {
        FaceQuery(hull_b, hull_a, world_from_b, world_from_a, first, separation, found);
      } else {
        FaceQuery(hull_a, hull_b, world_from_a, world_from_b, first, separation, found);
      }
      if (found >= 0) face = found, on_b = b_faces;
    };
    query(last_on_b_, last_face_);
    if (separation <= 0) query(!last_on_b_, 0);
    if (face < 0) face = 0, on_b = last_on_b_;  // a hull without faces: nothing to clip
    last_face_ = face;
    last_on_b_ = on_b;
    const btConvexPolyhedron& owner = on_b ? hull_b : hull_a;
    if (separation <= 0 && face < owner.m_faces.size()) {
      const btScalar* plane = owner.m_faces[face].m_plane;
      const btVector3 outward = (on_b ? world_from_b : world_from_a).getBasis() * btVector3(plane[0], plane[1], plane[2]);
      // Bullet's clipping takes the normal from B towards A.
      const btVector3 normal = on_b ? outward : -outward;
      vertices_1_.resize(0);
      btPolyhedralContactClipping::clipHullAgainstHull(normal, hull_a, hull_b, world_from_a, world_from_b,
                                                       -std::numeric_limits<btScalar>::max(),
                                                       manifold_->getContactBreakingThreshold(), vertices_1_,
                                                       vertices_2_, *result);
    }
    if (own_manifold_) result->refreshContactPoints();
  }

  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return btScalar(1);
  }

  void getAllContactManifolds(btManifoldArray& manifolds) override {
    if (manifold_ != nullptr && own_manifold_) manifolds.push_back(manifold_);
  }

 private:
  btPersistentManifold* manifold_;
  bool own_manifold_ = false;
  // The face of the last step's greatest separation, and whether it is B's.
  int last_face_ = 0;
  bool last_on_b_ = false;
  btVertexArray vertices_1_, vertices_2_;
};

bool ManyEdgeDirections(const btCollisionShape& shape) {
  const btConvexPolyhedron* hull = Polyhedron(shape);
  return hull != nullptr && hull->m_uniqueEdges.size() > kSeparatingAxisDirections;
}

struct FaceAxisCreate final : btCollisionAlgorithmCreateFunc {
  explicit FaceAxisCreate(btCollisionAlgorithmCreateFunc* fallback) : fallback(fallback) {}
  btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& info,
                                                 const btCollisionObjectWrapper* a,
                                                 const btCollisionObjectWrapper* b) override {
    const btCollisionShape& sa = *a->getCollisionShape();
    const btCollisionShape& sb = *b->getCollisionShape();
    const bool polyhedra = Polyhedron(sa) != nullptr && Polyhedron(sb) != nullptr;
    if (!polyhedra || (!ManyEdgeDirections(sa) && !ManyEdgeDirections(sb))) {
      return fallback->CreateCollisionAlgorithm(info, a, b);
    }
    void* memory = info.m_dispatcher1->allocateCollisionAlgorithm(sizeof(FaceAxisAlgorithm));
    return new (memory) FaceAxisAlgorithm(info, a, b);
  }
  btCollisionAlgorithmCreateFunc* fallback;
};

}  // namespace

bool Polyhedral(const btCollisionShape& shape) {
  if (shape.isCompound()) {
    const auto& compound = static_cast<const btCompoundShape&>(shape);
    for (int i = 0; i < compound.getNumChildShapes(); ++i) {
      if (!Polyhedral(*compound.getChildShape(i))) return false;
    }
    return compound.getNumChildShapes() > 0;
  }
  return Polyhedron(shape) != nullptr;
}

FaceAxisContacts::FaceAxisContacts() = default;
FaceAxisContacts::~FaceAxisContacts() = default;

void FaceAxisContacts::Register(btCollisionDispatcher& dispatcher, btCollisionConfiguration& configuration) {
  const int types[] = {BOX_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE};
  for (int t0 : types) {
    for (int t1 : types) {
      if (t0 == BOX_SHAPE_PROXYTYPE && t1 == BOX_SHAPE_PROXYTYPE) continue;
      created_.push_back(std::make_unique<FaceAxisCreate>(configuration.getCollisionAlgorithmCreateFunc(t0, t1)));
      dispatcher.registerCollisionCreateFunc(t0, t1, created_.back().get());
    }
  }
}

}  // namespace vscan::physics
