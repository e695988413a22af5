#include "reconstruction/poisson_pipeline.h"

#include <cmath>
#include <string>

#include "reconstruction/distance_trim.h"
#include "reconstruction/oriented_normals.h"
#include "reconstruction/poisson_process.h"
#include "reconstruction/stage_clock.h"
#include "reconstruction/stop_flag.h"

namespace vscan::reconstruction {
StatusOr<TriangleMesh> ReconstructPoisson(std::span<const ScanPoints> scans, const PoissonPipelineOptions& options,
                                          PoissonPipelineStats* stats, const std::atomic<bool>* cancel) {
  if (!(options.voxel_size > 0) || !std::isfinite(options.voxel_size)) {
    return InvalidArgument("poisson.voxel_size: must be finite and positive");
  }
  if (!(options.trim_voxels > 0) || !std::isfinite(options.trim_voxels)) {
    return InvalidArgument("poisson.trim_voxels: must be finite and positive");
  }
  PoissonPipelineStats s;
  auto t0 = StageClock::now();
  const UnionCloud cloud = VoxelDownsample(scans, options.voxel_size);
  s.union_points = cloud.positions.size();
  s.downsample_ms = MsSince(t0);
  if (options.max_memory_bytes > 0) {
    const uint64_t need = EstimatePoissonBytes(cloud.positions.size(), options.poisson.depth);
    if (need > options.max_memory_bytes) {
      return ResourceExhausted("poisson.depth", "depth " + std::to_string(options.poisson.depth) + " over " +
                                                    std::to_string(cloud.positions.size()) + " points needs about " +
                                                    std::to_string(need >> 20) + " MiB, more than the bound of " +
                                                    std::to_string(options.max_memory_bytes >> 20) + " MiB");
    }
  }
  if (Stopped(cancel)) return Cancelled("reconstruction stopped");
  t0 = StageClock::now();
  ASSIGN_OR_RETURN(OrientedCloud oriented, OrientNormals(cloud.positions, cloud.view_directions, options.normal_k));
  s.normals_ms = MsSince(t0);
  if (Stopped(cancel)) return Cancelled("reconstruction stopped");
  t0 = StageClock::now();
  ASSIGN_OR_RETURN(TriangleMesh mesh,
                   options.helper_path.empty()
                       ? PoissonPcl(oriented.positions, oriented.normals, options.poisson)
                       : PoissonInChild(options.helper_path, oriented.positions, oriented.normals, options.poisson,
                                        cancel, options.max_memory_bytes));
  if (Stopped(cancel)) return Cancelled("reconstruction stopped");
  s.poisson_ms = MsSince(t0);
  t0 = StageClock::now();
  TrimFarFromPoints(mesh, oriented.positions, options.trim_voxels * options.voxel_size);
  s.trim_ms = MsSince(t0);
  if (stats != nullptr) *stats = s;
  return mesh;
}

}  // namespace vscan::reconstruction
