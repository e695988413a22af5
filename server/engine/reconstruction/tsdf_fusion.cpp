#include "reconstruction/tsdf_fusion.h"

#include "reconstruction/marching_cubes.h"
#include "reconstruction/mesh_cleanup.h"
#include "reconstruction/stage_clock.h"
#include "reconstruction/stop_flag.h"

namespace vscan::reconstruction {

StatusOr<TriangleMesh> FuseRangeImages(std::span<const RangeImage> images, const TsdfFusionOptions& options,
                                       TsdfFusionStats* stats, const std::atomic<bool>* cancel) {
  TsdfFusionStats s;
  auto t0 = StageClock::now();
  ASSIGN_OR_RETURN(VoxelBlocks grid, IntegrateRangeImages(images, options.tsdf, cancel));
  s.blocks = grid.block_count();
  s.integrate_ms = MsSince(t0);
  t0 = StageClock::now();
  TriangleMesh mesh = ExtractMesh(grid, cancel);
  if (Stopped(cancel)) return Cancelled("tsdf: stopped");
  s.extract_ms = MsSince(t0);
  t0 = StageClock::now();
  RemoveSmallComponents(mesh, options.min_component_triangles);
  s.cleanup_ms = MsSince(t0);
  if (stats != nullptr) *stats = s;
  return mesh;
}

}  // namespace vscan::reconstruction
