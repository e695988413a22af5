#pragma once
// Approximate convex decomposition of a closed mesh (Bullet's HACD, kept inside the .cpp).

#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::physics {

// The convex pieces of the mesh, each as the points of its hull relative to `centre`, simplified
// within hull_tolerance_m (SimplifiedHull). A mesh HACD cannot split comes back as one piece: its
// hull.
std::vector<std::vector<Eigen::Vector3d>> ConvexPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                       double hull_tolerance_m);

}  // namespace vscan::physics
