#pragma once
// Distance from each query point to the nearest point of a set (kd-tree), in parallel.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "spatial/kd_tree.h"

namespace vscan::evaluation {

// +infinity for every query when the tree is empty, and for non-finite queries.
std::vector<float> NearestDistances(const spatial::KdTree& tree, std::span<const Eigen::Vector3f> queries);

}  // namespace vscan::evaluation
