#pragma once
// An indexed triangle mesh in metres.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace vscan {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;

  bool empty() const { return triangles.empty(); }
  // Axis-aligned bounds; both zero for an empty mesh.
  void Bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;
  // The volume a closed mesh encloses (signed tetrahedra from the origin): positive when its
  // triangles wind counter-clockwise seen from outside, so that their normals point out.
  double SignedVolume() const;
};

}  // namespace vscan
