#pragma once
// What every generated grasp list must be, whatever the gripper.

#include <vector>

#include "grasping/grasp_generation.h"

namespace vscan::grasping::testing {

// Qualities in [0, 1], best first; every tool frame a rotation (orthonormal, determinant > 0).
void ExpectSortedRigidGrasps(const std::vector<Grasp>& grasps);

}  // namespace vscan::grasping::testing
