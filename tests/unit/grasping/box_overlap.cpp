#include "box_overlap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vscan::grasping::testing {

bool TriangleMeetsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d centre = (lo + hi) / 2, half = (hi - lo) / 2;
  const std::array<Eigen::Vector3d, 3> v{a - centre, b - centre, c - centre};
  const std::array<Eigen::Vector3d, 3> edges{v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const auto separated = [&](const Eigen::Vector3d& axis) {
    if (axis.squaredNorm() < 1e-30) return false;  // parallel edges give no axis
    double tmin = v[0].dot(axis), tmax = tmin;
    for (int k = 1; k < 3; ++k) {
      tmin = std::min(tmin, v[k].dot(axis));
      tmax = std::max(tmax, v[k].dot(axis));
    }
    const double radius = half.cwiseProduct(axis.cwiseAbs()).sum();
    return tmin > radius || tmax < -radius;
  };
  for (int k = 0; k < 3; ++k) {
    if (separated(Eigen::Vector3d::Unit(k))) return false;
    for (const Eigen::Vector3d& e : edges) {
      if (separated(Eigen::Vector3d::Unit(k).cross(e))) return false;
    }
  }
  return !separated(edges[0].cross(edges[1]));
}

bool MeshMeetsBox(const TriangleMesh& mesh, const Pose3& box_from_mesh, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi) {
  for (const auto& t : mesh.triangles) {
    if (TriangleMeetsBox(box_from_mesh * mesh.vertices[t[0]].cast<double>(),
                         box_from_mesh * mesh.vertices[t[1]].cast<double>(),
                         box_from_mesh * mesh.vertices[t[2]].cast<double>(), lo, hi)) {
      return true;
    }
  }
  return false;
}

}  // namespace vscan::grasping::testing
