#pragma once
// Contacts between hulls of many edge directions from the separating-axis test over the hulls'
// face normals only (docs/PHYSICS.md, "The world").

#include <memory>
#include <vector>

class btCollisionAlgorithmCreateFunc;
class btCollisionConfiguration;
class btCollisionDispatcher;
class btCollisionShape;

namespace vscan::physics {

// Bullet's separating-axis test projects both hulls on each face normal and on the cross product of
// each pair of their edge directions. The fixture parts' hulls have 11-13 and a box 3; the machined
// riser's and 96-sided prism's 55 and 82, where the test on every pair made a fill of 20 of them
// 4.2x the CPU. Past this many on either hull the pair takes the face normals alone.
inline constexpr int kSeparatingAxisDirections = 32;

// Registered on a dispatcher: for pairs of hulls and boxes with polyhedral features where either
// has more than kSeparatingAxisDirections edge directions, a contact algorithm whose normal is the
// face normal of least overlap; other pairs keep the configuration's algorithm. Must outlive the
// dispatcher's pairs (declared before the dispatcher).
class FaceAxisContacts {
 public:
  FaceAxisContacts();
  ~FaceAxisContacts();
  void Register(btCollisionDispatcher& dispatcher, btCollisionConfiguration& configuration);

 private:
  std::vector<std::unique_ptr<btCollisionAlgorithmCreateFunc>> created_;
};

// Whether the shape has polyhedral features (a compound when each piece has).
bool Polyhedral(const btCollisionShape& shape);

}  // namespace vscan::physics
