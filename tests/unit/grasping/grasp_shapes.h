#pragma once
// Closed analytic meshes for grasp tests, metres, wound outwards.

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::grasping::testing {

// A cylinder of the given radius along z from 0 to height, its side cut into `segments` faces.
TriangleMesh MakeCylinder(double radius, double height, int segments);

// A square plate [-half, half]^2 x [0, thickness] with a square hole [-hole_half, hole_half]^2 through it.
TriangleMesh MakePlateWithHole(double half, double hole_half, double thickness);

// The same triangles wound the other way (normals in): a cavity when joined to an outer shell.
TriangleMesh Flipped(TriangleMesh mesh);

// Both meshes in one.
TriangleMesh Join(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace vscan::grasping::testing
