#include "reconstruction/voxel_blocks.h"

#include <algorithm>

#include "reconstruction/stop_flag.h"

namespace vscan::reconstruction {
namespace {

constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;

}  // namespace

uint64_t VoxelBlocks::Key(const Eigen::Vector3i& block) {
  return (static_cast<uint64_t>(block.x() + kCoordLimit) & kMask) |
         ((static_cast<uint64_t>(block.y() + kCoordLimit) & kMask) << 21) |
         ((static_cast<uint64_t>(block.z() + kCoordLimit) & kMask) << 42);
}

Eigen::Vector3i VoxelBlocks::BlockOfKey(uint64_t key) {
  return {static_cast<int>(key & kMask) - kCoordLimit, static_cast<int>((key >> 21) & kMask) - kCoordLimit,
          static_cast<int>((key >> 42) & kMask) - kCoordLimit};
}

bool VoxelBlocks::Allocate(const std::vector<uint64_t>& keys, const std::atomic<bool>* cancel) {
  constexpr size_t kChunkVoxels = size_t{1} << 20;
  coords_.reserve(coords_.size() + keys.size());
  index_.reserve(index_.size() + keys.size());
  for (uint64_t key : keys) {
    if (index_.emplace(key, static_cast<uint32_t>(coords_.size())).second) coords_.push_back(BlockOfKey(key));
  }
  const size_t total = coords_.size() * kVoxels;
  voxels_.reserve(total);
  while (voxels_.size() < total) {
    if (Stopped(cancel)) return false;
    voxels_.resize(std::min(total, voxels_.size() + kChunkVoxels));
  }
  return true;
}

int64_t VoxelBlocks::IndexOf(const Eigen::Vector3i& c) const {
  if ((c.array() < -kCoordLimit).any() || (c.array() >= kCoordLimit).any()) return -1;
  const auto it = index_.find(Key(c));
  return it == index_.end() ? -1 : int64_t{it->second};
}

}  // namespace vscan::reconstruction
