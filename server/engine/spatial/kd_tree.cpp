#include "spatial/kd_tree.h"

#include <algorithm>
#include <array>
#include <limits>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

namespace vscan::spatial {
namespace {

// Subtrees this large are built as parallel tasks.
constexpr uint32_t kParallelBuild = 1u << 14;

// The tree's shape depends only on point counts, so node ids can be assigned before building.
uint32_t NodeCount(uint32_t n) {
  if (n <= KdTree::kLeafSize) return 1;
  return 1 + NodeCount(n / 2) + NodeCount(n - n / 2);
}

uint32_t WidestDimension(std::span<const Eigen::Vector3f> points, const uint32_t* first,
                         const uint32_t* last) {
  Eigen::Array3f lo = points[*first].array();
  Eigen::Array3f hi = lo;
  for (const uint32_t* it = first + 1; it != last; ++it) {
    lo = lo.min(points[*it].array());
    hi = hi.max(points[*it].array());
  }
  Eigen::Array3f::Index dim = 0;
  (hi - lo).maxCoeff(&dim);
  return static_cast<uint32_t>(dim);
}

// Keeps the k best candidates as a max-heap on squared distance.
class BoundedHeap {
 public:
  BoundedHeap(std::span<Neighbor> storage, float max_dist_sq)
      : heap_(storage), max_dist_sq_(max_dist_sq) {}

  // Candidates must be closer than this to enter.
  float bound() const { return full() ? heap_[0].dist_sq : max_dist_sq_; }
  bool full() const { return size_ == heap_.size(); }
  size_t size() const { return size_; }

  void Offer(float dist_sq, uint32_t slot) {
    if (!full()) {
      if (dist_sq > max_dist_sq_) return;
      heap_[size_++] = {dist_sq, slot};
      std::push_heap(heap_.begin(), heap_.begin() + size_, Less{});
    } else if (dist_sq < heap_[0].dist_sq) {
      ReplaceTop({dist_sq, slot});
    }
  }

  // One sift-down instead of a pop and a push.
  void ReplaceTop(Neighbor item) {
    const size_t n = heap_.size();
    size_t hole = 0;
    for (size_t child = 1; child < n; child = 2 * hole + 1) {
      if (child + 1 < n && heap_[child + 1].dist_sq > heap_[child].dist_sq) ++child;
      if (heap_[child].dist_sq <= item.dist_sq) break;
      heap_[hole] = heap_[child];
      hole = child;
    }
    heap_[hole] = item;
  }

  void SortAscending() { std::sort_heap(heap_.begin(), heap_.begin() + size_, Less{}); }

 private:
  // A type, not a function pointer, so the heap algorithms inline it.
  struct Less {
    bool operator()(const Neighbor& x, const Neighbor& y) const { return x.dist_sq < y.dist_sq; }
  };

  std::span<Neighbor> heap_;
  float max_dist_sq_;
  size_t size_ = 0;
};

}  // namespace

KdTree::KdTree(std::span<const Eigen::Vector3f> points) {
  index_.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].allFinite()) index_.push_back(static_cast<uint32_t>(i));
  }
  if (index_.empty()) return;
  const auto n = static_cast<uint32_t>(index_.size());
  nodes_.resize(NodeCount(n));
  Build(0, 0, n, points);
  xs_.resize(n);
  ys_.resize(n);
  zs_.resize(n);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3f& p = points[index_[i]];
      xs_[i] = p.x();
      ys_[i] = p.y();
      zs_[i] = p.z();
    }
  });
}

void KdTree::Build(uint32_t node, uint32_t begin, uint32_t end, std::span<const Eigen::Vector3f> points) {
  const uint32_t n = end - begin;
  if (n <= kLeafSize) {
    nodes_[node] = {Node::kLeaf, 0.0f, begin, end};
    return;
  }
  uint32_t* first = index_.data() + begin;
  uint32_t* last = index_.data() + end;
  const uint32_t dim = WidestDimension(points, first, last);
  const uint32_t half = n / 2;
  std::nth_element(first, first + half, last,
                   [&](uint32_t x, uint32_t y) { return points[x][dim] < points[y][dim]; });
  const uint32_t right = node + 1 + NodeCount(half);
  nodes_[node] = {dim, points[first[half]][dim], right, 0};
  const uint32_t mid = begin + half;
  if (n >= kParallelBuild) {
    tbb::parallel_invoke([&] { Build(node + 1, begin, mid, points); },
                         [&] { Build(right, mid, end, points); });
  } else {
    Build(node + 1, begin, mid, points);
    Build(right, mid, end, points);
  }
}

template <class Bound, class Visit>
void KdTree::VisitLeaves(const Eigen::Vector3f& q, Bound bound, Visit visit) const {
  // A pending subtree with the query's per-axis offsets to its cell and their squared sum, a lower
  // bound on the distance to any point inside (incremental distance, Arya and Mount).
  struct Pending {
    uint32_t node;
    float dist_sq;
    std::array<float, 3> offset;
  };
  // Each pending entry is the far sibling of a node on the current path: at most one per level.
  std::array<Pending, 64> stack;
  size_t top = 0;
  stack[top++] = {0, 0.0f, {0.0f, 0.0f, 0.0f}};
  std::array<float, kLeafSize> dist_sq;
  while (top > 0) {
    Pending p = stack[--top];
    if (p.dist_sq > bound()) continue;
    uint32_t node = p.node;
    while (nodes_[node].dim != Node::kLeaf) {
      const Node& nd = nodes_[node];
      const float diff = q[nd.dim] - nd.split;
      const uint32_t near = diff < 0.0f ? node + 1 : nd.a;
      const uint32_t far = diff < 0.0f ? nd.a : node + 1;
      const float far_dist_sq = p.dist_sq - p.offset[nd.dim] * p.offset[nd.dim] + diff * diff;
      if (far_dist_sq <= bound()) {
        Pending& f = stack[top++];
        f = {far, far_dist_sq, p.offset};
        f.offset[nd.dim] = diff;
      }
      node = near;
    }
    const Node& leaf = nodes_[node];
    const uint32_t count = leaf.b - leaf.a;
    const float* xs = xs_.data() + leaf.a;
    const float* ys = ys_.data() + leaf.a;
    const float* zs = zs_.data() + leaf.a;
    for (uint32_t i = 0; i < count; ++i) {
      const float dx = xs[i] - q.x(), dy = ys[i] - q.y(), dz = zs[i] - q.z();
      dist_sq[i] = dx * dx + dy * dy + dz * dz;
    }
    visit(leaf.a, std::span<const float>(dist_sq.data(), count));
  }
}

size_t KdTree::Knn(const Eigen::Vector3f& q, float max_dist_sq, std::span<Neighbor> out) const {
  if (out.empty() || nodes_.empty()) return 0;
  BoundedHeap heap(out, max_dist_sq);
  VisitLeaves(
      q, [&heap] { return heap.bound(); },
      [&heap](uint32_t first, std::span<const float> dist_sq) {
        for (uint32_t i = 0; i < dist_sq.size(); ++i) {
          if (dist_sq[i] < heap.bound() || !heap.full()) heap.Offer(dist_sq[i], first + i);
        }
      });
  heap.SortAscending();
  return heap.size();
}

std::array<Neighbor, 2> KdTree::NearestTwo(const Eigen::Vector3f& q, float max_dist_sq) const {
  std::array<Neighbor, 2> best{{{max_dist_sq, kNoSlot}, {max_dist_sq, kNoSlot}}};
  if (nodes_.empty()) return best;
  // Closer than an entry, or within the limit while the entry is still empty.
  const auto better = [](float d, const Neighbor& entry) {
    return d < entry.dist_sq || (entry.slot == kNoSlot && d <= entry.dist_sq);
  };
  VisitLeaves(
      q, [&best] { return best[1].dist_sq; },
      [&](uint32_t first, std::span<const float> dist_sq) {
        for (uint32_t i = 0; i < dist_sq.size(); ++i) {
          const float d = dist_sq[i];
          if (!better(d, best[1])) continue;
          if (better(d, best[0])) {
            best[1] = best[0];
            best[0] = {d, first + i};
          } else {
            best[1] = {d, first + i};
          }
        }
      });
  return best;
}

}  // namespace vscan::spatial
