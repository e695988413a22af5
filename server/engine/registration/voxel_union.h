#pragma once
// The aligned scans merged on one voxel grid in the model frame: per voxel the centroid of the
// points that fell in it and the mean of their normals. Its size follows the surface scanned, not
// the number of scans, so aligning against it stays as fast for the fortieth scan as for the second.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace vscan::registration {

class VoxelUnion {
 public:
  // voxel_size > 0 (metres).
  explicit VoxelUnion(double voxel_size);

  // Adds points (model frame) with one normal each; a non-finite normal adds the position only.
  // Points without a voxel key (non-finite, or farther than 2^20 voxels out) are skipped.
  void Add(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals);
  void Clear();

  // One point per occupied voxel, in the order the voxels were first filled.
  const std::vector<Eigen::Vector3f>& points() const { return points_; }
  // The unit mean of each voxel's normals; NaN when it has none or when they disagree so much that
  // their mean is short (the two sides of a thin wall in one voxel).
  const std::vector<Eigen::Vector3f>& normals() const { return normals_; }
  size_t size() const { return points_.size(); }

 private:
  struct Voxel {
    Eigen::Vector3d point_sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
    uint32_t points = 0;
    uint32_t normals = 0;
  };

  double inverse_voxel_size_;
  std::unordered_map<uint64_t, uint32_t> slot_of_key_;
  std::vector<Voxel> voxels_;
  std::vector<Eigen::Vector3f> points_;
  std::vector<Eigen::Vector3f> normals_;
};

}  // namespace vscan::registration
