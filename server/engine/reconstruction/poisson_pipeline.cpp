#include "reconstruction/poisson_pipeline.h"

#include <cmath>

#include "reconstruction/distance_trim.h"
#include "reconstruction/oriented_normals.h"
#include "reconstruction/stage_clock.h"

namespace vscan::reconstruction {

StatusOr<TriangleMesh> ReconstructPoisson(std::span<const ScanPoints> scans, const PoissonPipelineOptions& options,
                                          PoissonPipelineStats* stats) {
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
  t0 = StageClock::now();
  ASSIGN_OR_RETURN(OrientedCloud oriented, OrientNormals(cloud.positions, cloud.view_directions, options.normal_k));
  s.normals_ms = MsSince(t0);
  t0 = StageClock::now();
  ASSIGN_OR_RETURN(TriangleMesh mesh, PoissonPcl(oriented.positions, oriented.normals, options.poisson));
  s.poisson_ms = MsSince(t0);
  t0 = StageClock::now();
  TrimFarFromPoints(mesh, oriented.positions, options.trim_voxels * options.voxel_size);
  s.trim_ms = MsSince(t0);
  if (stats != nullptr) *stats = s;
  return mesh;
}

}  // namespace vscan::reconstruction
