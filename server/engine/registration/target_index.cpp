#include "registration/target_index.h"

#include <limits>

namespace vscan::registration {
namespace {

// Points whose normal is unusable become NaN, which the kd-tree leaves out.
std::vector<Eigen::Vector3f> UsablePoints(std::span<const Eigen::Vector3f> points,
                                          std::span<const Eigen::Vector3f> normals) {
  std::vector<Eigen::Vector3f> usable(points.begin(), points.end());
  const Eigen::Vector3f nan = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
  for (size_t i = 0; i < usable.size(); ++i) {
    if (!normals[i].allFinite() || normals[i].squaredNorm() == 0.0f) usable[i] = nan;
  }
  return usable;
}

}  // namespace

TargetIndex::TargetIndex(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals)
    : tree_(UsablePoints(points, normals)) {
  normals_.resize(tree_.size());
  for (uint32_t slot = 0; slot < tree_.size(); ++slot) {
    normals_[slot] = normals[tree_.original_index(slot)];
    centroid_ += tree_.point(slot).cast<double>();
  }
  if (tree_.size() > 0) centroid_ /= static_cast<double>(tree_.size());
}

}  // namespace vscan::registration
