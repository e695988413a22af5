// The exact diameter of a point set without comparing every pair: a dual-tree search over a k-d
// tree of the points, which opens a pair of nodes only when the farthest corners of their boxes
// could beat the longest pair found so far, the farther children first.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "localization/pose_errors.h"

namespace vscan::localization {
namespace {

constexpr size_t kLeafPoints = 16;

struct Node {
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
  uint32_t begin = 0, end = 0;       // points[begin, end)
  int32_t left = -1, right = -1;     // children; -1 for a leaf
};

class DiameterSearch {
 public:
  explicit DiameterSearch(std::span<const Eigen::Vector3f> vertices) : points_(vertices.size()) {
    for (size_t i = 0; i < vertices.size(); ++i) points_[i] = vertices[i].cast<double>();
    nodes_.reserve(2 * (points_.size() / kLeafPoints + 1));
    Build(0, static_cast<uint32_t>(points_.size()));
  }

  double Squared() {
    best_ = SeedSquared();
    Search(0, 0);
    return best_;
  }

 private:
  int32_t Build(uint32_t begin, uint32_t end) {
    const auto index = static_cast<int32_t>(nodes_.size());
    nodes_.push_back({});
    Node node;
    node.begin = begin;
    node.end = end;
    node.min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    node.max = -node.min;
    for (uint32_t i = begin; i < end; ++i) {
      node.min = node.min.cwiseMin(points_[i]);
      node.max = node.max.cwiseMax(points_[i]);
    }
    if (end - begin > kLeafPoints) {
      int axis = 0;
      (node.max - node.min).maxCoeff(&axis);
      const uint32_t mid = begin + (end - begin) / 2;
      std::nth_element(points_.begin() + begin, points_.begin() + mid, points_.begin() + end,
                       [axis](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a[axis] < b[axis]; });
      node.left = Build(begin, mid);
      node.right = Build(mid, end);
    }
    nodes_[static_cast<size_t>(index)] = node;
    return index;
  }

  // The largest squared distance between a point of box a and a point of box b.
  static double FarthestSquared(const Node& a, const Node& b) {
    return (a.max - b.min).cwiseAbs().cwiseMax((b.max - a.min).cwiseAbs()).squaredNorm();
  }

  void Search(int32_t ia, int32_t ib) {
    const Node& a = nodes_[static_cast<size_t>(ia)];
    const Node& b = nodes_[static_cast<size_t>(ib)];
    if (FarthestSquared(a, b) <= best_) return;
    if (a.left < 0 && b.left < 0) {
      for (uint32_t i = a.begin; i < a.end; ++i) {
        for (uint32_t j = (ia == ib ? i + 1 : b.begin); j < b.end; ++j) {
          best_ = std::max(best_, (points_[i] - points_[j]).squaredNorm());
        }
      }
      return;
    }
    if (ia == ib) {
      Search(a.left, a.right);
      Search(a.left, a.left);
      Search(a.right, a.right);
      return;
    }
    // Split the larger node; visit the child pair with the larger bound first.
    const bool split_a = b.left < 0 || (a.left >= 0 && (a.end - a.begin) >= (b.end - b.begin));
    const int32_t keep = split_a ? ib : ia;
    const Node& split = split_a ? a : b;
    int32_t first = split.left, second = split.right;
    const Node& kept = nodes_[static_cast<size_t>(keep)];
    if (FarthestSquared(nodes_[static_cast<size_t>(second)], kept) >
        FarthestSquared(nodes_[static_cast<size_t>(first)], kept)) {
      std::swap(first, second);
    }
    Search(first, keep);
    Search(second, keep);
  }

  // Two sweeps of "the point farthest from the last": a pair at or near the diameter to start from.
  double SeedSquared() const {
    size_t from = 0;
    double best = 0;
    for (int sweep = 0; sweep < 2; ++sweep) {
      size_t farthest = from;
      double far_sq = 0;
      for (size_t i = 0; i < points_.size(); ++i) {
        const double d = (points_[i] - points_[from]).squaredNorm();
        if (d > far_sq) far_sq = d, farthest = i;
      }
      best = std::max(best, far_sq);
      from = farthest;
    }
    return best;
  }

  std::vector<Eigen::Vector3d> points_;
  std::vector<Node> nodes_;
  double best_ = 0;
};

}  // namespace

double Diameter(std::span<const Eigen::Vector3f> vertices) {
  if (vertices.size() < 2) return 0;
  return std::sqrt(DiameterSearch(vertices).Squared());
}

}  // namespace vscan::localization
