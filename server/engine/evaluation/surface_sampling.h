#pragma once
// Points drawn uniformly by area on a triangle mesh, the same for a given seed on every machine.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::evaluation {

double SurfaceArea(const TriangleMesh& mesh);

// count points, each on a triangle chosen with probability proportional to its area and uniform
// within it. Draw i depends only on (seed, i), so the result does not depend on the thread count.
// face_normals, when given, receives each sample's triangle's unit normal (by its winding).
std::vector<Eigen::Vector3f> SampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed,
                                           std::vector<Eigen::Vector3f>* face_normals = nullptr);

}  // namespace vscan::evaluation
