#pragma once
// What every Bullet fill world shares: pose conversions, the bin as static boxes and the deepest
// contacts. Bullet types are only declared here; the .cpp files that use them include Bullet.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "physics/bin_fill.h"
#include "physics/fill_world.h"

class btVector3;
class btTransform;
class btCollisionShape;
class btRigidBody;
class btDiscreteDynamicsWorld;
class btTriangleMesh;

namespace vscan::physics {

btVector3 ToBullet(const Eigen::Vector3d& v);
btTransform ToBullet(const Pose3& pose);
Pose3 FromBullet(const btTransform& transform);

// The floor and four walls, or the bin's mesh as one static concave shape (its triangles kept in
// triangles); add the bodies to a world and remove them before it is destroyed.
struct BinBodies {
  BinBodies();
  ~BinBodies();
  BinBodies(BinBodies&&) noexcept;
  BinBodies& operator=(BinBodies&&) noexcept;

  std::unique_ptr<btTriangleMesh> triangles;  // a mesh bin's; outlives the shape that refers to it
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
};

// Bullet's default box margin (4 cm) is thicker than a wall, so the margin is always given.
BinBodies MakeBinBodies(const BinSpec& bin, double friction, double margin);

// Runs a collision pass and reads every contact manifold: part-bin when one body is static.
ContactDepths DeepestContactsOf(btDiscreteDynamicsWorld& world);

}  // namespace vscan::physics
