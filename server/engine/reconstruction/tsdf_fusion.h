#pragma once
// Range images with known poses to a mesh: TSDF integration, marching cubes, clean-up.

#include <atomic>
#include <cstddef>
#include <span>

#include "reconstruction/range_image.h"
#include "reconstruction/tsdf_integration.h"
#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

struct TsdfFusionOptions {
  TsdfOptions tsdf;
  // Connected pieces with fewer triangles than this are dropped; 0 keeps all.
  size_t min_component_triangles = 0;
};

struct TsdfFusionStats {
  size_t blocks = 0;
  double integrate_ms = 0;
  double extract_ms = 0;
  double cleanup_ms = 0;
};

// CANCELLED soon after *cancel becomes true, whatever the stage.
StatusOr<TriangleMesh> FuseRangeImages(std::span<const RangeImage> images, const TsdfFusionOptions& options,
                                       TsdfFusionStats* stats = nullptr, const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::reconstruction
