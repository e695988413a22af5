#pragma once
// The target cloud as ICP queries it: a kd-tree over the points whose position and normal are
// finite, with the normals stored in the tree's slot order next to the points.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "spatial/kd_tree.h"

namespace vscan::registration {

class TargetIndex {
 public:
  TargetIndex(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals);

  size_t size() const { return tree_.size(); }
  const spatial::KdTree& tree() const { return tree_; }
  Eigen::Vector3f point(uint32_t slot) const { return tree_.point(slot); }
  const Eigen::Vector3f& normal(uint32_t slot) const { return normals_[slot]; }
  // Mean of the indexed points, a well-conditioned centre to linearise rotations about.
  const Eigen::Vector3d& centroid() const { return centroid_; }

 private:
  spatial::KdTree tree_;
  std::vector<Eigen::Vector3f> normals_;
  Eigen::Vector3d centroid_ = Eigen::Vector3d::Zero();
};

}  // namespace vscan::registration
