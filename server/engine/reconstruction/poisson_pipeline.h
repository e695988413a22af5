#pragma once
// Scans to a mesh through Poisson: union cloud evened out by voxels, normals turned towards the
// sensors, PCL's Poisson, then trimming where nothing was seen.

#include <atomic>
#include <cstdint>
#include <span>
#include <string>

#include "reconstruction/poisson_pcl.h"
#include "reconstruction/union_cloud.h"
#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

struct PoissonPipelineOptions {
  // Edge of the voxels that even out the union's density, metres.
  float voxel_size = 0.001f;
  // Neighbours per normal estimate.
  int normal_k = 16;
  PoissonOptions poisson;
  // Vertices farther than this from every union point are trimmed, in voxel_size units.
  float trim_voxels = 2.0f;
  // The vscan-poisson executable that solves in a child process; empty solves in this process.
  std::string helper_path;
  // RESOURCE_EXHAUSTED naming "poisson.depth" when EstimatePoissonBytes passes this; 0: no bound.
  uint64_t max_memory_bytes = 0;
};

struct PoissonPipelineStats {
  size_t union_points = 0;
  double downsample_ms = 0;
  double normals_ms = 0;
  double poisson_ms = 0;
  double trim_ms = 0;
};

// InvalidArgument names "poisson.voxel_size", "poisson.trim_voxels" or a normals or Poisson option.
// CANCELLED when *cancel becomes true: between stages, and at once during a child's solve.
StatusOr<TriangleMesh> ReconstructPoisson(std::span<const ScanPoints> scans, const PoissonPipelineOptions& options,
                                          PoissonPipelineStats* stats = nullptr,
                                          const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::reconstruction
