#include "reconstruction/marching_cubes.h"

#include <array>
#include <vector>

#include <tbb/parallel_for.h>

#include "reconstruction/cube_cases.h"
#include "reconstruction/mesh_cleanup.h"
#include "reconstruction/stop_flag.h"

namespace vscan::reconstruction {
namespace {

constexpr int kSide = VoxelBlocks::kSide;
constexpr int kNone = -1;

// A block and the seven blocks after it (+x, +y, +z and their combinations), which hold the
// far corners of its last layer of cubes.
using NeighbourIndex = std::array<int64_t, 8>;

NeighbourIndex NeighboursOf(const VoxelBlocks& grid, size_t b) {
  NeighbourIndex index;
  const Eigen::Vector3i c = grid.block_coord(b);
  for (int i = 0; i < 8; ++i) index[i] = grid.IndexOf(c + Eigen::Vector3i(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  return index;
}

struct Neighbourhood {
  std::array<const TsdfVoxel*, 8> blocks{};

  Neighbourhood(const VoxelBlocks& grid, const NeighbourIndex& index) {
    for (int i = 0; i < 8; ++i) blocks[i] = index[i] < 0 ? nullptr : grid.block(static_cast<size_t>(index[i]));
  }

  // Voxel at local coordinates in [0, 2 * kSide); nullptr when its block is absent.
  const TsdfVoxel* At(int x, int y, int z) const {
    const int which = (x >= kSide ? 1 : 0) | (y >= kSide ? 2 : 0) | (z >= kSide ? 4 : 0);
    const TsdfVoxel* block = blocks[which];
    if (block == nullptr) return nullptr;
    return block + VoxelBlocks::Local(x % kSide, y % kSide, z % kSide);
  }
};

bool Observed(const TsdfVoxel* v) { return v != nullptr && v->weight > 0; }

// Vertices on the three edges leaving each voxel of a block in +x, +y and +z.
struct BlockVertices {
  std::vector<Eigen::Vector3f> positions;
  std::vector<int32_t> edge_vertex;  // [local voxel * 3 + axis] -> index in positions, or kNone
  uint32_t first = 0;                // index of positions[0] in the whole mesh
};

void FindVertices(const VoxelBlocks& grid, size_t b, const NeighbourIndex& neighbours, BlockVertices& out) {
  const Neighbourhood hood(grid, neighbours);
  const float voxel = grid.voxel_size();
  const Eigen::Vector3i origin = grid.block_coord(b) * kSide;
  out.edge_vertex.assign(VoxelBlocks::kVoxels * 3, kNone);
  for (int z = 0; z < kSide; ++z) {
    for (int y = 0; y < kSide; ++y) {
      for (int x = 0; x < kSide; ++x) {
        const TsdfVoxel* v0 = hood.At(x, y, z);
        if (!Observed(v0)) continue;
        for (int a = 0; a < 3; ++a) {
          const TsdfVoxel* v1 = hood.At(x + (a == 0), y + (a == 1), z + (a == 2));
          if (!Observed(v1) || (v0->sdf < 0) == (v1->sdf < 0)) continue;
          const float t = v0->sdf / (v0->sdf - v1->sdf);
          Eigen::Vector3f p = (origin + Eigen::Vector3i(x, y, z)).cast<float>();
          p[a] += t;
          out.edge_vertex[VoxelBlocks::Local(x, y, z) * 3 + a] = static_cast<int32_t>(out.positions.size());
          out.positions.push_back(p * voxel);
        }
      }
    }
  }
}

void MakeTriangles(const VoxelBlocks& grid, const std::vector<BlockVertices>& vertices,
                   const NeighbourIndex& neighbours, std::vector<std::array<uint32_t, 3>>& out) {
  const Neighbourhood hood(grid, neighbours);
  std::array<const TsdfVoxel*, 8> corner;
  for (int z = 0; z < kSide; ++z) {
    for (int y = 0; y < kSide; ++y) {
      for (int x = 0; x < kSide; ++x) {
        uint32_t mask = 0;
        bool complete = true;
        for (int c = 0; c < 8 && complete; ++c) {
          corner[c] = hood.At(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
          complete = Observed(corner[c]);
          if (complete && corner[c]->sdf < 0) mask |= 1u << c;
        }
        if (!complete || mask == 0 || mask == 255) continue;
        // Only where something was measured: free space carved beside the band behind an edge
        // would otherwise hang a skirt from every silhouette down to the truncation depth.
        bool measured_in = false, measured_out = false;
        for (int c = 0; c < 8; ++c) {
          if (corner[c]->near_surface == 0) continue;
          (corner[c]->sdf < 0 ? measured_in : measured_out) = true;
        }
        if (!measured_in || !measured_out) continue;
        for (const CubeTriangle& tri : CubeCase(mask)) {
          std::array<uint32_t, 3> ids;
          for (int k = 0; k < 3; ++k) {
            const int start = EdgeStart(tri[k]);
            const int ex = x + (start & 1), ey = y + ((start >> 1) & 1), ez = z + ((start >> 2) & 1);
            const int which = (ex >= kSide ? 1 : 0) | (ey >= kSide ? 2 : 0) | (ez >= kSide ? 4 : 0);
            const BlockVertices& owner = vertices[static_cast<size_t>(neighbours[which])];
            const int32_t local =
                owner.edge_vertex[VoxelBlocks::Local(ex % kSide, ey % kSide, ez % kSide) * 3 + EdgeAxis(tri[k])];
            ids[k] = owner.first + static_cast<uint32_t>(local);
          }
          out.push_back(ids);
        }
      }
    }
  }
}

}  // namespace

TriangleMesh ExtractMesh(const VoxelBlocks& grid, const std::atomic<bool>* cancel) {
  const size_t n = grid.block_count();
  std::vector<NeighbourIndex> neighbours(n);
  std::vector<BlockVertices> vertices(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4), [&](const tbb::blocked_range<size_t>& r) {
    if (Stopped(cancel)) return;
    for (size_t b = r.begin(); b != r.end(); ++b) {
      neighbours[b] = NeighboursOf(grid, b);
      FindVertices(grid, b, neighbours[b], vertices[b]);
    }
  });
  TriangleMesh mesh;
  if (Stopped(cancel)) return mesh;
  uint32_t total = 0;
  for (BlockVertices& v : vertices) {
    v.first = total;
    total += static_cast<uint32_t>(v.positions.size());
  }
  mesh.vertices.reserve(total);
  for (const BlockVertices& v : vertices) mesh.vertices.insert(mesh.vertices.end(), v.positions.begin(), v.positions.end());

  std::vector<std::vector<std::array<uint32_t, 3>>> triangles(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4), [&](const tbb::blocked_range<size_t>& r) {
    if (Stopped(cancel)) return;
    for (size_t b = r.begin(); b != r.end(); ++b) MakeTriangles(grid, vertices, neighbours[b], triangles[b]);
  });
  size_t count = 0;
  for (const auto& t : triangles) count += t.size();
  mesh.triangles.reserve(count);
  for (const auto& t : triangles) mesh.triangles.insert(mesh.triangles.end(), t.begin(), t.end());
  DropUnusedVertices(mesh);
  return mesh;
}

}  // namespace vscan::reconstruction
