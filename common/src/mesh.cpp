#include "vscan/common/mesh.h"

#include <Eigen/Geometry>

namespace vscan {

void TriangleMesh::Bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const {
  if (vertices.empty()) {
    min.setZero();
    max.setZero();
    return;
  }
  min = max = vertices.front();
  for (const auto& v : vertices) {
    min = min.cwiseMin(v);
    max = max.cwiseMax(v);
  }
}

double TriangleMesh::SignedVolume() const {
  double six_volume = 0;
  for (const auto& t : triangles) {
    const Eigen::Vector3d a = vertices[t[0]].cast<double>(), b = vertices[t[1]].cast<double>(),
                          c = vertices[t[2]].cast<double>();
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6;
}

}  // namespace vscan
