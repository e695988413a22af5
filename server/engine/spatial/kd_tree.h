#pragma once
// A flat, balanced kd-tree for k-nearest-neighbour queries on 3D points.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::spatial {

// One search result: a tree slot and its squared distance to the query.
struct Neighbor {
  float dist_sq;
  uint32_t slot;
};

// Points are copied in leaf order, so a leaf is a contiguous run and consecutive slots are
// spatially close. Non-finite points are left out of the tree.
class KdTree {
 public:
  static constexpr uint32_t kLeafSize = 16;

  explicit KdTree(std::span<const Eigen::Vector3f> points);

  // Writes the (at most out.size()) nearest points within sqrt(max_dist_sq) of q to out, nearest
  // first, and returns how many were found. Pass infinity for no distance limit.
  size_t Knn(const Eigen::Vector3f& q, float max_dist_sq, std::span<Neighbor> out) const;

  static constexpr uint32_t kNoSlot = ~uint32_t{0};
  // The two nearest points within sqrt(max_dist_sq) of q, nearest first; a missing one has slot
  // kNoSlot and distance max_dist_sq. Like Knn with k = 2 without the heap. A tight limit (e.g.
  // from points known to be near) prunes most of the tree.
  std::array<Neighbor, 2> NearestTwo(const Eigen::Vector3f& q, float max_dist_sq) const;

  size_t size() const { return index_.size(); }
  Eigen::Vector3f point(uint32_t slot) const { return {xs_[slot], ys_[slot], zs_[slot]}; }
  // Index of a slot's point in the span given to the constructor.
  uint32_t original_index(uint32_t slot) const { return index_[slot]; }

 private:
  // Internal: split dimension, split value, right child (the left child is the next node).
  // Leaf: begin and end slots, with dim == kLeaf.
  struct Node {
    static constexpr uint32_t kLeaf = 3;
    uint32_t dim;
    float split;
    uint32_t a;
    uint32_t b;
  };

  void Build(uint32_t node, uint32_t begin, uint32_t end, std::span<const Eigen::Vector3f> points);
  // Visits, nearest first, the leaves whose cells lie within bound() of q, passing each leaf's
  // first slot and its points' squared distances to q.
  template <class Bound, class Visit>
  void VisitLeaves(const Eigen::Vector3f& q, Bound bound, Visit visit) const;

  std::vector<Node> nodes_;
  // Coordinates by axis so that a leaf's distances vectorise.
  std::vector<float> xs_, ys_, zs_;
  std::vector<uint32_t> index_;
};

}  // namespace vscan::spatial
