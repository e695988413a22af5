#pragma once
// Truncated signed distance fusion of range images with known poses (Curless and Levoy 1996) into a
// sparse voxel grid: blocks are allocated along each pixel's ray near its surface point, then every
// block integrates every image in parallel.

#include <atomic>
#include <cstdint>
#include <span>

#include "reconstruction/range_image.h"
#include "reconstruction/voxel_blocks.h"
#include "vscan/common/status.h"

namespace vscan::reconstruction {

struct TsdfOptions {
  // Edge of a voxel, metres.
  float voxel_size = 0.001f;
  // Distances are clamped to +-truncation_voxels * voxel_size; voxels farther behind a surface than
  // that are left alone. In [1, 8).
  float truncation_voxels = 4.0f;
  // A pixel that saw nothing within the camera's range marks the voxels on its ray as free space
  // (with a small weight), which closes the surface along silhouettes and the edges of what was
  // seen. Right for ray-cast scans, where no hit means no surface; turn it off for sensors that
  // drop returns on dark or shiny surfaces.
  bool carve_empty_pixels = true;
  // The voxel blocks may take at most this many bytes (0: no bound); past it the integration ends
  // with RESOURCE_EXHAUSTED naming tsdf.voxel_size before any block is allocated.
  uint64_t max_block_bytes = 0;
};

// InvalidArgument names "tsdf.voxel_size", "tsdf.truncation_voxels" or "images[i]..."; see
// max_block_bytes for RESOURCE_EXHAUSTED. CANCELLED soon after *cancel becomes true: every loop
// checks it per chunk of rows or blocks.
StatusOr<VoxelBlocks> IntegrateRangeImages(std::span<const RangeImage> images, const TsdfOptions& options,
                                           const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::reconstruction
