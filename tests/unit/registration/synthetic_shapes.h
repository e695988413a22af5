#pragma once
// Exact point clouds for registration tests: points on a box and a sphere with their true normals.

#include <cstdint>

#include "reference_pair.h"

namespace vscan::registration::testing {

// `count` points spread over the surfaces of a 0.20 x 0.15 x 0.10 m box centred at the origin and a
// sphere of radius 0.05 m centred at (0.17, 0.02, 0.03), in proportion to their areas, with outward
// normals. The same seed gives the same cloud.
Cloud BoxAndSphere(size_t count, uint32_t seed);

// The cloud moved by a rigid transform, normals included.
Cloud Moved(const Cloud& cloud, const Pose3& pose);

}  // namespace vscan::registration::testing
