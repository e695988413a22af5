#pragma once
// First hits of rays on a triangle mesh: a brute-force Moller-Trumbore test over every triangle
// (cost: triangles per ray; the callers bound the number of rays).

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::grasping {

struct RayHit {
  double distance = 0;
  Eigen::Vector3d normal;  // unit face normal of the triangle hit
};

class MeshRays {
 public:
  explicit MeshRays(const TriangleMesh& mesh);
  // The nearest hit at a distance in (min_distance, max_distance] along the unit direction.
  std::optional<RayHit> FirstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                 double min_distance, double max_distance) const;

 private:
  struct Triangle {
    Eigen::Vector3d a, edge1, edge2, normal;
  };
  std::vector<Triangle> triangles_;
};

}  // namespace vscan::grasping
