#include "vscan/common/mesh.h"

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

}  // namespace vscan
