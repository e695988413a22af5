#pragma once
// Meshes and geometry helpers for the ray-cast tests.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::test {

// A square of side 2 * half_size centred on centre, perpendicular to normal (two triangles).
TriangleMesh MakeSquare(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double half_size);

// An icosahedron subdivided `levels` times, vertices pushed onto the sphere.
TriangleMesh MakeIcosphere(const Eigen::Vector3d& centre, double radius, int levels);

// Vertices and faces of an ASCII PLY file; fails the calling test (empty mesh) on error.
TriangleMesh ReadAsciiPly(const std::string& path);

// Distance from p to triangle (a, b, c).
double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// Distance from p to the nearest triangle of mesh (brute force).
double DistanceToMesh(const Eigen::Vector3d& p, const TriangleMesh& mesh);

inline std::shared_ptr<const TriangleMesh> Share(TriangleMesh mesh) {
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

}  // namespace vscan::test
