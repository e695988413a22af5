#include "reconstruction/tsdf_fusion.h"

#include <chrono>

#include "reconstruction/marching_cubes.h"
#include "reconstruction/mesh_cleanup.h"

namespace vscan::reconstruction {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

StatusOr<TriangleMesh> FuseRangeImages(std::span<const RangeImage> images, const TsdfFusionOptions& options,
                                       TsdfFusionStats* stats) {
  TsdfFusionStats s;
  auto t0 = Clock::now();
  ASSIGN_OR_RETURN(VoxelBlocks grid, IntegrateRangeImages(images, options.tsdf));
  s.blocks = grid.block_count();
  s.integrate_ms = MsSince(t0);
  t0 = Clock::now();
  TriangleMesh mesh = ExtractMesh(grid);
  s.extract_ms = MsSince(t0);
  t0 = Clock::now();
  RemoveSmallComponents(mesh, options.min_component_triangles);
  s.cleanup_ms = MsSince(t0);
  if (stats != nullptr) *stats = s;
  return mesh;
}

}  // namespace vscan::reconstruction
