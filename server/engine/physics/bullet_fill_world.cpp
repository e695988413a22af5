#include "physics/bullet_fill_world.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>

#include "physics/bullet_shared.h"
#include "physics/face_axis_contacts.h"

namespace vscan::physics {
namespace {

// The separating-axis test for pairs of polyhedra, a compound's pieces each on their own: Bullet's
// where both have few edge directions, FaceAxisContacts' (face normals only) where one has many.
// Not for a mesh bin's triangles.
void SeparatingAxisWhereCheap(btBroadphasePair& pair, btCollisionDispatcher& dispatcher, const btDispatcherInfo& info) {
  const auto* a = static_cast<btCollisionObject*>(pair.m_pProxy0->m_clientObject);
  const auto* b = static_cast<btCollisionObject*>(pair.m_pProxy1->m_clientObject);
  btDispatcherInfo chosen = info;
  chosen.m_enableSatConvex = Polyhedral(*a->getCollisionShape()) && Polyhedral(*b->getCollisionShape());
  btCollisionDispatcher::defaultNearCallback(pair, dispatcher, chosen);
}

class BulletFillWorld final : public FillWorld {
 public:
  BulletFillWorld(const BinSpec& bin, const std::vector<PartGeometry>& geometry, const FillOptions& options)
      : options_(options), dispatcher_(&configuration_),
        world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {
    world_.setGravity(btVector3(0, 0, btScalar(-9.81)));
    world_.getSolverInfo().m_numIterations = options.solver_iterations;
    bin_ = MakeBinBodies(bin, options.friction, options.collision_margin_m);
    if (options.polyhedral_contacts && options.separating_axis_contacts) {
      // The separating-axis test picks the contact normal among the hulls' face normals and edge
      // pairs; without it Bullet takes it from GJK/EPA, which on a pin across a block's edge gave
      // normals along which the clipped contacts read 0.01 mm while the hulls overlapped by 5 mm.
      dispatcher_.setNearCallback(&SeparatingAxisWhereCheap);
      face_axes_.Register(dispatcher_, configuration_);
      // The bin's boxes get faces too, so that a part against the floor or a wall is clipped
      // against them instead of one GJK point a step (parts ended 2.5 mm into walls without).
      for (auto& shape : bin_.shapes) {
        if (auto* box = dynamic_cast<btBoxShape*>(shape.get())) box->initializePolyhedralFeatures();
      }
    }
    for (auto& wall : bin_.bodies) world_.addRigidBody(wall.get());
    for (const PartGeometry& part : geometry) {
      TypeShape type{HullShape(part.hull), {}, btScalar(part.mass_kg), btVector3(0, 0, 0)};
      // The hull's inertia for either shape: a compound's own is that of its bounding box.
      type.shape->calculateLocalInertia(type.mass, type.inertia);
      if (!part.pieces.empty()) {
        auto compound = std::make_unique<btCompoundShape>(true, static_cast<int>(part.pieces.size()));
        for (const auto& piece : part.pieces) {
          type.pieces.push_back(HullShape(piece));
          compound->addChildShape(btTransform::getIdentity(), type.pieces.back().get());
        }
        type.shape = std::move(compound);
      }
      shapes_.push_back(std::move(type));
    }
  }

  ~BulletFillWorld() override {
    for (auto& body : bodies_) {
      if (body) world_.removeRigidBody(body.get());
    }
    for (auto& wall : bin_.bodies) world_.removeRigidBody(wall.get());
  }

  size_t AddPart(size_t type, const Pose3& world_from_body) override {
    const TypeShape& shape = shapes_[type];
    btRigidBody::btRigidBodyConstructionInfo info(shape.mass, nullptr, shape.shape.get(), shape.inertia);
    info.m_startWorldTransform = ToBullet(world_from_body);
    info.m_friction = btScalar(options_.friction);
    info.m_restitution = btScalar(options_.restitution);
    info.m_rollingFriction = btScalar(options_.rolling_friction_m);
    info.m_spinningFriction = btScalar(options_.rolling_friction_m);
    info.m_linearDamping = btScalar(options_.linear_damping);
    info.m_angularDamping = btScalar(options_.angular_damping);
    info.m_linearSleepingThreshold = btScalar(options_.sleep_linear_m_per_s);
    info.m_angularSleepingThreshold = btScalar(options_.sleep_angular_rad_per_s);
    auto body = std::make_unique<btRigidBody>(info);
    if (options_.sleep_linear_m_per_s == 0 || options_.sleep_angular_rad_per_s == 0) {
      body->setActivationState(DISABLE_DEACTIVATION);
    }
    world_.addRigidBody(body.get());
    bodies_.push_back(std::move(body));
    return bodies_.size() - 1;
  }

  void RemovePart(size_t body) override {
    world_.removeRigidBody(bodies_[body].get());
    bodies_[body].reset();
  }

  void Step() override {
    const auto substeps = options_.substeps;
    world_.stepSimulation(btScalar(options_.time_step_s), substeps, btScalar(options_.time_step_s / substeps));
  }

  void SetDamping(double damping) override {
    for (auto& body : bodies_) {
      if (body) body->setDamping(btScalar(damping), btScalar(damping));
    }
  }

  BodyState State(size_t body) const override {
    const btRigidBody& b = *bodies_[body];
    return {FromBullet(b.getWorldTransform()), static_cast<double>(b.getLinearVelocity().length()),
            static_cast<double>(b.getAngularVelocity().length())};
  }

  ContactDepths DeepestContacts() override { return DeepestContactsOf(world_); }

 private:
  struct TypeShape {
    std::unique_ptr<btCollisionShape> shape;  // the hull, or the compound of the pieces
    std::vector<std::unique_ptr<btCollisionShape>> pieces;
    btScalar mass;
    btVector3 inertia;
  };

  std::unique_ptr<btCollisionShape> HullShape(const std::vector<Eigen::Vector3d>& points,
                                              bool polyhedral = true) const {
    auto shape = std::make_unique<btConvexHullShape>();
    for (const auto& p : points) shape->addPoint(ToBullet(p), false);
    shape->recalcLocalAabb();
    shape->setMargin(btScalar(options_.collision_margin_m));
    if (options_.polyhedral_contacts && polyhedral) {
      shape->initializePolyhedralFeatures();
    }
    return shape;
  }

  const FillOptions options_;
  btDefaultCollisionConfiguration configuration_;
  FaceAxisContacts face_axes_;  // before the dispatcher, which holds its create functions
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  BinBodies bin_;
  std::vector<TypeShape> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

}  // namespace

std::unique_ptr<FillWorld> MakeBulletFillWorld(const BinSpec& bin, const std::vector<PartGeometry>& geometry,
                                               const FillOptions& options) {
  return std::make_unique<BulletFillWorld>(bin, geometry, options);
}

}  // namespace vscan::physics
