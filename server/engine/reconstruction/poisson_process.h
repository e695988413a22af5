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

// The least PoissonPcl takes for this many points at this depth: a lower envelope of the peaks
// measured on spheres, nested shells, noisy spheres and walls (docs/OPERATIONS.md). Refusing on it
// turns away only solves that cannot fit; the child's data limit (PoissonInChild) bounds the rest,
// since the real peak depends on the surface's shape (up to 8x this at depth 8).
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

// The helper's exit status when an allocation fails (its memory bound reached).
inline constexpr int kPoissonOutOfMemoryExit = 5;

// Runs PoissonPcl in helper_path; the same mesh as in-process. CANCELLED (the child killed)
// within about 20 ms of *cancel becoming true; UNAVAILABLE when the helper cannot be started;
// RESOURCE_EXHAUSTED naming "poisson.depth" when the child's data passes max_memory_bytes (0: no
// bound); INTERNAL when it dies otherwise.
StatusOr<TriangleMesh> PoissonInChild(const std::string& helper_path, std::span<const Eigen::Vector3f> points,
                                      std::span<const Eigen::Vector3f> normals, const PoissonOptions& options,
                                      const std::atomic<bool>* cancel, uint64_t max_memory_bytes = 0);

}  // namespace vscan::reconstruction
