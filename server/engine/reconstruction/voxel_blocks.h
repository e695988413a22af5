#pragma once
// A sparse grid of TSDF voxels: 8^3-voxel blocks allocated only near observed surfaces, found
// through a hash map from block coordinates, so memory follows the surface.

#include <atomic>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace vscan::reconstruction {

struct TsdfVoxel {
  float sdf = 0;     // metres, clamped to [-truncation, truncation]; > 0 in front of the surface
  float weight = 0;  // observations; 0 means never observed
  // 1 once a measured depth put the voxel within one voxel of its surface.
  uint32_t near_surface = 0;
};

class VoxelBlocks {
 public:
  static constexpr int kSide = 8;
  static constexpr int kVoxels = kSide * kSide * kSide;
  // Block coordinates must lie in [-kCoordLimit, kCoordLimit) on each axis.
  static constexpr int kCoordLimit = 1 << 20;

  // Voxel (i, j, k) of the grid has its centre at voxel_size * (i, j, k).
  explicit VoxelBlocks(float voxel_size) : voxel_size_(voxel_size) {}

  static uint64_t Key(const Eigen::Vector3i& block);
  static Eigen::Vector3i BlockOfKey(uint64_t key);
  static int Local(int x, int y, int z) { return (z * kSide + y) * kSide + x; }

  // Allocates the blocks of the given keys (sorted, unique) with unobserved voxels; false when
  // *cancel became true first (a GiB of voxels takes seconds to clear).
  bool Allocate(const std::vector<uint64_t>& keys, const std::atomic<bool>* cancel = nullptr);

  float voxel_size() const { return voxel_size_; }
  size_t block_count() const { return coords_.size(); }
  const Eigen::Vector3i& block_coord(size_t b) const { return coords_[b]; }
  TsdfVoxel* block(size_t b) { return voxels_.data() + b * kVoxels; }
  const TsdfVoxel* block(size_t b) const { return voxels_.data() + b * kVoxels; }
  // Index of the block at block coordinates c, or -1 when it is not allocated.
  int64_t IndexOf(const Eigen::Vector3i& c) const;

 private:
  float voxel_size_;
  std::vector<Eigen::Vector3i> coords_;
  std::vector<TsdfVoxel> voxels_;
  std::unordered_map<uint64_t, uint32_t> index_;
};

}  // namespace vscan::reconstruction
