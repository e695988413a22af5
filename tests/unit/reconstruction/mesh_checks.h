#pragma once
// Mesh properties the reconstruction tests check: closedness, orientation, distance to a surface.

#include <map>
#include <utility>

#include <Eigen/Geometry>

#include "vscan/common/mesh.h"

namespace vscan::reconstruction::test {

// Every directed edge appears once and its reverse once: closed, manifold along edges, and
// consistently wound.
inline bool ClosedAndConsistent(const TriangleMesh& mesh) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return !mesh.triangles.empty();
}

// Share of triangles whose normal points away from centre.
inline double ShareFacingAway(const TriangleMesh& mesh, const Eigen::Vector3f& centre) {
  size_t away = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3f a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    if ((b - a).cross(c - a).dot((a + b + c) / 3 - centre) > 0) ++away;
  }
  return mesh.triangles.empty() ? 0 : static_cast<double>(away) / mesh.triangles.size();
}

}  // namespace vscan::reconstruction::test
