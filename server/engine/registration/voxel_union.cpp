#include "registration/voxel_union.h"

#include <limits>

#include "registration/voxel_thinning.h"

namespace vscan::registration {
namespace {

// A mean of unit normals shorter than this is no direction.
constexpr double kMinMeanNormalLength = 0.5;

}  // namespace

VoxelUnion::VoxelUnion(double voxel_size) : inverse_voxel_size_(1.0 / voxel_size) {}

void VoxelUnion::Add(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals) {
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  for (size_t i = 0; i < points.size(); ++i) {
    const std::optional<uint64_t> key = VoxelKey(points[i], inverse_voxel_size_);
    if (!key) continue;
    const auto [it, inserted] = slot_of_key_.try_emplace(*key, static_cast<uint32_t>(voxels_.size()));
    if (inserted) {
      voxels_.emplace_back();
      points_.push_back(nan);
      normals_.push_back(nan);
    }
    const uint32_t slot = it->second;
    Voxel& voxel = voxels_[slot];
    voxel.point_sum += points[i].cast<double>();
    ++voxel.points;
    points_[slot] = (voxel.point_sum / voxel.points).cast<float>();
    if (!normals[i].allFinite()) continue;
    voxel.normal_sum += normals[i].cast<double>();
    ++voxel.normals;
    const double length = voxel.normal_sum.norm();
    normals_[slot] = length >= kMinMeanNormalLength * voxel.normals ? (voxel.normal_sum / length).cast<float>() : nan;
  }
}

void VoxelUnion::Clear() {
  slot_of_key_.clear();
  voxels_.clear();
  points_.clear();
  normals_.clear();
}

}  // namespace vscan::registration
