#include "physics/bullet_shared.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>

namespace vscan::physics {

btVector3 ToBullet(const Eigen::Vector3d& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}

btTransform ToBullet(const Pose3& pose) {
  const Eigen::Matrix3d r = pose.linear();
  const btMatrix3x3 basis(btScalar(r(0, 0)), btScalar(r(0, 1)), btScalar(r(0, 2)), btScalar(r(1, 0)),
                          btScalar(r(1, 1)), btScalar(r(1, 2)), btScalar(r(2, 0)), btScalar(r(2, 1)),
                          btScalar(r(2, 2)));
  return btTransform(basis, ToBullet(Eigen::Vector3d(pose.translation())));
}

Pose3 FromBullet(const btTransform& transform) {
  Pose3 pose = Pose3::Identity();
  const btMatrix3x3& basis = transform.getBasis();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose.linear()(i, j) = static_cast<double>(basis[i][j]);
  }
  const btVector3& t = transform.getOrigin();
  pose.translation() = Eigen::Vector3d(t.x(), t.y(), t.z());
  return pose;
}

BinBodies::BinBodies() = default;
BinBodies::~BinBodies() = default;
BinBodies::BinBodies(BinBodies&&) noexcept = default;
BinBodies& BinBodies::operator=(BinBodies&&) noexcept = default;

namespace {

BinBodies MakeMeshBinBodies(const BinSpec& bin, double friction, double margin) {
  BinBodies out;
  out.triangles = std::make_unique<btTriangleMesh>();
  for (const auto& t : bin.mesh.triangles) {
    const auto corner = [&](int k) { return ToBullet(Eigen::Vector3d(bin.mesh.vertices[t[k]].cast<double>())); };
    out.triangles->addTriangle(corner(0), corner(1), corner(2));
  }
  auto shape = std::make_unique<btBvhTriangleMeshShape>(out.triangles.get(), true);
  // The triangles have no thickness: a thin part falling several millimetres a step went through
  // a floor of a few large triangles with the parts' 0.5 mm; four times that catches it.
  shape->setMargin(btScalar(4 * margin));
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
  info.m_startWorldTransform = ToBullet(bin.world_from_bin);
  info.m_friction = btScalar(friction);
  out.bodies.push_back(std::make_unique<btRigidBody>(info));
  out.shapes.push_back(std::move(shape));
  return out;
}

}  // namespace

BinBodies MakeBinBodies(const BinSpec& bin, double friction, double margin) {
  if (!bin.mesh.empty()) return MakeMeshBinBodies(bin, friction, margin);
  const double sx = bin.inner_size.x(), sy = bin.inner_size.y(), sz = bin.inner_size.z();
  const double w = bin.wall_thickness;
  struct Slab {
    Eigen::Vector3d half_extents;
    Eigen::Vector3d centre;  // bin frame
  };
  // The long walls cover the corners so that no seam opens between walls.
  const Slab slabs[] = {
      {{0.5 * sx + w, 0.5 * sy + w, 0.5 * w}, {0, 0, -0.5 * w}},
      {{0.5 * w, 0.5 * sy + w, 0.5 * sz}, {0.5 * (sx + w), 0, 0.5 * sz}},
      {{0.5 * w, 0.5 * sy + w, 0.5 * sz}, {-0.5 * (sx + w), 0, 0.5 * sz}},
      {{0.5 * sx, 0.5 * w, 0.5 * sz}, {0, 0.5 * (sy + w), 0.5 * sz}},
      {{0.5 * sx, 0.5 * w, 0.5 * sz}, {0, -0.5 * (sy + w), 0.5 * sz}},
  };
  BinBodies out;
  for (const Slab& slab : slabs) {
    auto shape = std::make_unique<btBoxShape>(ToBullet(slab.half_extents));
    shape->setMargin(btScalar(margin));
    Pose3 bin_from_slab = Pose3::Identity();
    bin_from_slab.translation() = slab.centre;
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape.get());
    info.m_startWorldTransform = ToBullet(bin.world_from_bin * bin_from_slab);
    info.m_friction = btScalar(friction);
    out.bodies.push_back(std::make_unique<btRigidBody>(info));
    out.shapes.push_back(std::move(shape));
  }
  return out;
}

ContactDepths DeepestContactsOf(btDiscreteDynamicsWorld& world) {
  world.performDiscreteCollisionDetection();
  ContactDepths out;
  btDispatcher& dispatcher = *world.getDispatcher();
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(m);
    const bool with_bin = manifold.getBody0()->isStaticObject() || manifold.getBody1()->isStaticObject();
    double& deepest = with_bin ? out.part_bin : out.part_part;
    for (int c = 0; c < manifold.getNumContacts(); ++c) {
      deepest = std::max(deepest, -static_cast<double>(manifold.getContactPoint(c).getDistance()));
    }
  }
  return out;
}

}  // namespace vscan::physics
