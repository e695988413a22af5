#pragma once
// An open tote with sloped walls as bare triangles (no thickness): a bin given as a mesh.

#include "vscan/common/mesh.h"

namespace vscan::physics::test {

// The floor (floor_x by floor_y) at z = 0 centred in x and y, the opening (top_x by top_y) at
// z = depth, four flat walls between their edges; metres.
TriangleMesh SlopedTote(float floor_x, float floor_y, float top_x, float top_y, float depth);

}  // namespace vscan::physics::test
