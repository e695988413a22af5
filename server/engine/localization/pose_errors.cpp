#include "localization/pose_errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "spatial/kd_tree.h"

namespace vscan::localization {
namespace {

Eigen::Vector3d Placed(const Pose3& pose, const Eigen::Vector3f& v) { return pose * v.cast<double>(); }

}  // namespace

double AddError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth) {
  if (vertices.empty()) return 0;
  double sum = 0;
  for (const auto& v : vertices) sum += (Placed(estimate, v) - Placed(truth, v)).norm();
  return sum / static_cast<double>(vertices.size());
}

double AddSError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth) {
  if (vertices.empty()) return 0;
  // BOP's adi: from each vertex under the truth to the nearest vertex under the estimate, not the
  // other way round (the two differ on parts sampled unevenly). Taken in the estimate's part frame,
  // where the kd-tree holds the vertices as given.
  const Pose3 estimate_from_truth = estimate.inverse() * truth;
  const spatial::KdTree tree(vertices);
  std::array<spatial::Neighbor, 1> nearest{};
  double sum = 0;
  for (const auto& v : vertices) {
    const Eigen::Vector3d q = estimate_from_truth * v.cast<double>();
    tree.Knn(q.cast<float>(), std::numeric_limits<float>::infinity(), nearest);
    sum += (q - tree.point(nearest[0].slot).cast<double>()).norm();
  }
  return sum / static_cast<double>(vertices.size());
}

double MssdError(std::span<const Eigen::Vector3f> vertices, const Pose3& estimate, const Pose3& truth,
                 std::span<const Pose3> symmetries) {
  const Pose3 identity = Pose3::Identity();
  const std::span<const Pose3> transforms = symmetries.empty() ? std::span<const Pose3>(&identity, 1) : symmetries;
  double best = std::numeric_limits<double>::infinity();
  for (const Pose3& s : transforms) {
    const Pose3 symmetric_truth = truth * s;
    double worst_sq = 0;
    for (const auto& v : vertices) {
      worst_sq = std::max(worst_sq, (Placed(estimate, v) - Placed(symmetric_truth, v)).squaredNorm());
      if (worst_sq >= best * best) break;  // this transform cannot beat the best one
    }
    best = std::min(best, std::sqrt(worst_sq));
  }
  return vertices.empty() ? 0 : best;
}

}  // namespace vscan::localization
