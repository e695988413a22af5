#pragma once
// Analytic triangle meshes for the tests: squares, grids, spheres and boxes.

#include <memory>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::test {

// A square of side 2 * half_size centred on centre, perpendicular to normal, wound
// counter-clockwise seen from the side normal points to (two triangles).
TriangleMesh MakeSquare(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double half_size);

// A square of side 2 * half_side in the xy plane, normal +z, split into cells x cells pairs of
// triangles.
TriangleMesh MakeGrid(double half_side, int cells);

// An icosahedron subdivided `levels` times, vertices pushed onto the sphere.
TriangleMesh MakeIcosphere(const Eigen::Vector3d& centre, double radius, int levels);

// A UV sphere of the given radius centred on the origin.
TriangleMesh MakeUvSphere(double radius, int rings, int segments);

// The axis-aligned box [lo, hi], 12 triangles wound outwards.
TriangleMesh MakeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

inline std::shared_ptr<const TriangleMesh> Share(TriangleMesh mesh) {
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

}  // namespace vscan::test
