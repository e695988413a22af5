#pragma once
// Screened Poisson surface reconstruction (Kazhdan and Hoppe) through PCL's pcl::Poisson; PCL
// stays in the .cpp file.

#include <span>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

struct PoissonOptions {
  // Octree depth: at most 2^depth cells along the bounding cube's edge.
  int depth = 8;
  // Threads PCL may use; 0 means every core.
  int threads = 0;
};

// normals must be unit and face outwards, one per point. The mesh is closed: it covers unseen
// parts too, so trim it (TrimFarFromPoints) before scoring it.
StatusOr<TriangleMesh> PoissonPcl(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                                  const PoissonOptions& options);

}  // namespace vscan::reconstruction
