#pragma once
// Machined parts made procedurally, whose convex hulls have 100-300 vertices: a riser (a block
// with round bosses on top and pockets cut into it) and a many-sided prism. Closed meshes, metres.

#include "vscan/common/mesh.h"

namespace vscan::physics::test {

// 40 x 30 mm block, 12 mm high, two round bosses (6 mm radius, 5-6 mm high, crowned) and two 4 mm
// deep pockets, as a height field on a 1 mm grid closed by walls and a floor.
TriangleMesh Riser();

// A prism of `sides` sides around z, `radius` to its corners, `height` tall.
TriangleMesh ManySidedPrism(int sides = 96, double radius = 0.012, double height = 0.02);

// A ring about z: 5 cm to the middle of its 2 cm tube, n x n/2 quads (n^2 triangles).
TriangleMesh Torus(int n);

}  // namespace vscan::physics::test
