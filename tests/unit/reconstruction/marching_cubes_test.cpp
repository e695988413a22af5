#include "reconstruction/marching_cubes.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "mesh_checks.h"

namespace vscan::reconstruction {
namespace {

constexpr float kVoxel = 0.01f;

// A grid holding the exact signed distance of a sphere, clamped to the truncation, in every
// block within the band.
VoxelBlocks SphereGrid(const Eigen::Vector3f& centre, float radius, float truncation) {
  VoxelBlocks grid(kVoxel);
  const float block = kVoxel * VoxelBlocks::kSide;
  std::vector<uint64_t> keys;
  const int lo = static_cast<int>(std::floor((-radius - truncation - block) / block)) - 1;
  const int hi = -lo + 1;
  for (int z = lo; z <= hi; ++z) {
    for (int y = lo; y <= hi; ++y) {
      for (int x = lo; x <= hi; ++x) keys.push_back(VoxelBlocks::Key({x, y, z}));
    }
  }
  std::sort(keys.begin(), keys.end());
  grid.Allocate(keys);
  for (size_t b = 0; b < grid.block_count(); ++b) {
    TsdfVoxel* voxels = grid.block(b);
    for (int z = 0; z < VoxelBlocks::kSide; ++z) {
      for (int y = 0; y < VoxelBlocks::kSide; ++y) {
        for (int x = 0; x < VoxelBlocks::kSide; ++x) {
          const Eigen::Vector3f p =
              (grid.block_coord(b) * VoxelBlocks::kSide + Eigen::Vector3i(x, y, z)).cast<float>() * kVoxel;
          const float sdf = (p - centre).norm() - radius;
          if (sdf < -truncation) continue;  // never observed, as behind a real surface
          voxels[VoxelBlocks::Local(x, y, z)] = {std::min(sdf, truncation), 1.0f, std::abs(sdf) <= kVoxel};
        }
      }
    }
  }
  return grid;
}

TEST(MarchingCubes, SphereIsClosedOutwardAndOnTheSurface) {
  const Eigen::Vector3f centre(0.013f, -0.021f, 0.007f);
  constexpr float kRadius = 0.2f;
  const TriangleMesh mesh = ExtractMesh(SphereGrid(centre, kRadius, 4 * kVoxel));
  ASSERT_GT(mesh.triangles.size(), 1000u);
  EXPECT_TRUE(test::ClosedAndConsistent(mesh));
  EXPECT_EQ(test::ShareFacingAway(mesh, centre), 1.0);
  for (const auto& v : mesh.vertices) {
    // Linear interpolation of an exact distance field: error far below a voxel.
    EXPECT_NEAR((v - centre).norm(), kRadius, 0.05f * kVoxel);
  }
}

TEST(MarchingCubes, UnobservedCornersLeaveNoTriangles) {
  VoxelBlocks grid(kVoxel);
  grid.Allocate({VoxelBlocks::Key({0, 0, 0})});
  EXPECT_TRUE(ExtractMesh(grid).empty());
  // One observed sign change without observed neighbours around it still gives no cube.
  grid.block(0)[VoxelBlocks::Local(1, 1, 1)] = {-1.0f, 1.0f, 1};
  grid.block(0)[VoxelBlocks::Local(2, 1, 1)] = {1.0f, 1.0f, 1};
  EXPECT_TRUE(ExtractMesh(grid).empty());
}

}  // namespace
}  // namespace vscan::reconstruction
