#pragma once
// An ordering of a cloud's points along a space-filling curve, so that points close in the order
// are close in space.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::registration {

// Indices of the finite points, sorted by their Morton (Z-order) code on a 2^21 grid over the
// bounding box, ties by index.
std::vector<uint32_t> MortonOrder(std::span<const Eigen::Vector3f> points);

}  // namespace vscan::registration
