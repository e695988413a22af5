#pragma once
// Bullet's HACD (libHACD, Bullet's extras) as vscan used it before its plane cuts: clusters with
// concavity at 2% of the part's size, merged while the union's hull adds at most 3% of the part's
// hull volume. The peer of decomposition_bench.

#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::bench {

std::vector<std::vector<Eigen::Vector3d>> HacdPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre);

}  // namespace vscan::bench
