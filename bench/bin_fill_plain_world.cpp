#include "bin_fill_plain_world.h"

#include <btBulletDynamicsCommon.h>

#include "physics/bullet_shared.h"

namespace vscan::bench {
namespace {

// PyBullet's URDF and mesh importer margin (gUrdfDefaultCollisionMargin).
constexpr double kImporterMargin = 0.001;

using physics::BodyState;
using physics::ContactDepths;

class PlainFillWorld final : public physics::FillWorld {
 public:
  PlainFillWorld(const physics::BinSpec& bin, const std::vector<physics::PartType>& parts,
                 const std::vector<physics::PartGeometry>& geometry, const physics::FillOptions& materials)
      : materials_(materials), dispatcher_(&configuration_),
        world_(&dispatcher_, &broadphase_, &solver_, &configuration_) {
    world_.setGravity(btVector3(0, 0, btScalar(-9.81)));
    btContactSolverInfo& info = world_.getSolverInfo();
    info.m_erp2 = btScalar(0.08);
    info.m_frictionERP = btScalar(0.2);
    info.m_linearSlop = btScalar(0.00001);
    info.m_numIterations = 50;
    info.m_minimumSolverBatchSize = 0;
    info.m_warmstartingFactor = btScalar(0.1);
    info.m_leastSquaresResidualThreshold = btScalar(1e-7);
    bin_ = physics::MakeBinBodies(bin, materials.friction, kImporterMargin);
    for (auto& wall : bin_.bodies) world_.addRigidBody(wall.get());
    for (size_t t = 0; t < parts.size(); ++t) {
      auto shape = std::make_unique<btConvexHullShape>();
      for (const Eigen::Vector3f& v : parts[t].mesh.vertices) {
        shape->addPoint(physics::ToBullet(Eigen::Vector3d(v.cast<double>() - geometry[t].centre)), false);
      }
      shape->recalcLocalAabb();
      shape->setMargin(btScalar(kImporterMargin));
      btVector3 inertia(0, 0, 0);
      shape->calculateLocalInertia(btScalar(geometry[t].mass_kg), inertia);
      shapes_.push_back({std::move(shape), btScalar(geometry[t].mass_kg), inertia});
    }
  }

  ~PlainFillWorld() override {
    for (auto& body : bodies_) {
      if (body) world_.removeRigidBody(body.get());
    }
    for (auto& wall : bin_.bodies) world_.removeRigidBody(wall.get());
  }

  size_t AddPart(size_t type, const Pose3& world_from_body) override {
    const TypeShape& shape = shapes_[type];
    btRigidBody::btRigidBodyConstructionInfo info(shape.mass, nullptr, shape.shape.get(), shape.inertia);
    info.m_startWorldTransform = physics::ToBullet(world_from_body);
    info.m_friction = btScalar(materials_.friction);
    info.m_restitution = btScalar(materials_.restitution);
    info.m_rollingFriction = btScalar(materials_.rolling_friction_m);
    info.m_spinningFriction = btScalar(materials_.rolling_friction_m);
    info.m_linearDamping = btScalar(materials_.linear_damping);
    info.m_angularDamping = btScalar(materials_.angular_damping);
    auto body = std::make_unique<btRigidBody>(info);
    body->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(body.get());
    bodies_.push_back(std::move(body));
    return bodies_.size() - 1;
  }

  void RemovePart(size_t body) override {
    world_.removeRigidBody(bodies_[body].get());
    bodies_[body].reset();
  }

  void Step() override { world_.stepSimulation(btScalar(1.0 / 240.0), 0, btScalar(1.0 / 240.0)); }

  void SetDamping(double damping) override {
    for (auto& body : bodies_) {
      if (body) body->setDamping(btScalar(damping), btScalar(damping));
    }
  }

  BodyState State(size_t body) const override {
    const btRigidBody& b = *bodies_[body];
    return {physics::FromBullet(b.getWorldTransform()), static_cast<double>(b.getLinearVelocity().length()),
            static_cast<double>(b.getAngularVelocity().length())};
  }

  ContactDepths DeepestContacts() override { return physics::DeepestContactsOf(world_); }

 private:
  struct TypeShape {
    std::unique_ptr<btConvexHullShape> shape;
    btScalar mass;
    btVector3 inertia;
  };

  const physics::FillOptions materials_;
  btDefaultCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  physics::BinBodies bin_;
  std::vector<TypeShape> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

}  // namespace

std::unique_ptr<physics::FillWorld> MakePlainFillWorld(const physics::BinSpec& bin,
                                                       const std::vector<physics::PartType>& parts,
                                                       const std::vector<physics::PartGeometry>& geometry,
                                                       const physics::FillOptions& materials) {
  return std::make_unique<PlainFillWorld>(bin, parts, geometry, materials);
}

}  // namespace vscan::bench
