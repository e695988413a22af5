#pragma once
// The zero level set of a sparse TSDF grid as a triangle mesh (marching cubes, parallel over blocks).

#include <atomic>

#include "reconstruction/voxel_blocks.h"
#include "vscan/common/mesh.h"

namespace vscan::reconstruction {

// Cubes with an unobserved corner, or with no corner near a measured surface, are skipped. Each grid edge the surface crosses gives exactly one
// vertex, shared by every triangle that uses it (welded by construction); triangles face the side
// of positive distance (the sensors' side).
TriangleMesh ExtractMesh(const VoxelBlocks& grid, const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::reconstruction
