#pragma once
// Trimming a closed surface fitted to a cloud back to where the cloud is. PCL's Poisson reports no
// sample densities, so low density is judged by distance: a vertex farther than max_distance from
// every input point lies where nothing was seen.

#include <span>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::reconstruction {

// Drops the vertices farther than max_distance from all points, the triangles on them and then the
// unused vertices. Returns how many triangles were dropped.
size_t TrimFarFromPoints(TriangleMesh& mesh, std::span<const Eigen::Vector3f> points, float max_distance);

}  // namespace vscan::reconstruction
