#pragma once
// Brute-force point-to-mesh distances, the reference the scanners' hit points are checked against.

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::test {

// Distance from p to triangle (a, b, c).
double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// Distance from p to the nearest triangle of mesh.
double DistanceToMesh(const Eigen::Vector3d& p, const TriangleMesh& mesh);

}  // namespace vscan::test
