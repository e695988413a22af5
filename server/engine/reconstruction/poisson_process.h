#pragma once
// Screened Poisson in a child process (the vscan-poisson helper), so that a stopped job kills the
// solver at once instead of waiting for PCL, which cannot be interrupted; plus the frames the
// two processes exchange and an up-front estimate of the solver's memory.

#include <atomic>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "reconstruction/poisson_pcl.h"
#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

// Peak bytes of PoissonPcl for this many points at this depth, an upper estimate measured on
// scanned objects (docs/BENCHMARKS.md): the octree grows with the surface, about 4^depth cells.
uint64_t EstimatePoissonBytes(size_t points, int depth);

// Frames, native byte order (both ends are the same build on the same machine).
std::string EncodePoissonInput(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                               const PoissonOptions& options);
struct PoissonInput {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
  PoissonOptions options;
};
StatusOr<PoissonInput> DecodePoissonInput(std::string_view bytes);
std::string EncodePoissonResult(const TriangleMesh& mesh);
StatusOr<TriangleMesh> DecodePoissonResult(std::string_view bytes);

// Runs PoissonPcl in helper_path; the same mesh as in-process. CANCELLED (the child killed)
// within about 20 ms of *cancel becoming true; UNAVAILABLE when the helper cannot be started;
// INTERNAL when it dies (for instance killed for memory).
StatusOr<TriangleMesh> PoissonInChild(const std::string& helper_path, std::span<const Eigen::Vector3f> points,
                                      std::span<const Eigen::Vector3f> normals, const PoissonOptions& options,
                                      const std::atomic<bool>* cancel);

}  // namespace vscan::reconstruction
