#pragma once
// The normal of a least-squares plane through a small neighbourhood.

#include <span>

#include <Eigen/Core>

#include "spatial/kd_tree.h"

namespace vscan::normals {

// Centroid, centred 3x3 covariance, and the unit eigenvector of its smallest eigenvalue (Eigen's
// closed-form SelfAdjointEigenSolver::computeDirect). That is the right singular vector of the
// smallest singular value of the centred neighbourhood matrix, without forming an SVD. The sign is
// arbitrary. Needs at least one neighbour.
Eigen::Vector3f FitPlaneNormal(const spatial::KdTree& tree, std::span<const spatial::Neighbor> neighbours);

}  // namespace vscan::normals
