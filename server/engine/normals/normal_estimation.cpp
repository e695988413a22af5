#include "normals/normal_estimation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <tbb/parallel_for.h>

#include "spatial/kd_tree.h"
#include "normals/plane_fit.h"

namespace vscan::normals {
namespace {

constexpr int kMinK = 3;
constexpr int kMaxK = 256;
// Slots per task: a few leaves, enough to amortise scheduling, small enough to balance.
constexpr uint32_t kGrain = 256;

Status Validate(std::span<const Eigen::Vector3f> points, const NormalOptions& options) {
  if (options.k < kMinK || options.k > kMaxK) {
    return InvalidArgument("normals.k must be in [3, 256], got " + std::to_string(options.k));
  }
  if (!std::isfinite(options.max_distance) || options.max_distance < 0.0f) {
    return InvalidArgument("normals.max_distance must be finite and >= 0, got " +
                           std::to_string(options.max_distance));
  }
  if (points.size() > std::numeric_limits<uint32_t>::max()) {
    return InvalidArgument("normals: at most 2^32-1 points, got " + std::to_string(points.size()));
  }
  return Status::Ok();
}

bool IsCancelled(const NormalOptions& options) {
  return options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
}

// The previous query's k neighbours are k distinct points, so the farthest of them from p bounds
// p's k-th neighbour distance: searching within it gives the same answer and prunes from the start.
// Consecutive slots are close in space, which keeps the bound tight. The slack covers rounding.
float SeedBound(const spatial::KdTree& tree, const Eigen::Vector3f& p,
                std::span<const spatial::Neighbor> previous) {
  float bound = 0.0f;
  for (const spatial::Neighbor& nb : previous) bound = std::max(bound, (tree.point(nb.slot) - p).squaredNorm());
  return bound * (1.0f + 1e-5f) + std::numeric_limits<float>::min();
}

}  // namespace

StatusOr<std::vector<Eigen::Vector3f>> EstimateNormals(std::span<const Eigen::Vector3f> points,
                                                        const NormalOptions& options) {
  RETURN_IF_ERROR(Validate(points, options));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Eigen::Vector3f> normals(points.size(), Eigen::Vector3f::Constant(nan));
  const spatial::KdTree tree(points);
  if (IsCancelled(options)) return Cancelled("normals: cancelled");

  const float max_dist_sq = options.max_distance > 0.0f
                                ? options.max_distance * options.max_distance
                                : std::numeric_limits<float>::infinity();
  const auto k = static_cast<size_t>(options.k);
  const auto n = static_cast<uint32_t>(tree.size());
  // Queries run in leaf order so that neighbouring tasks touch neighbouring memory.
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kGrain), [&](const tbb::blocked_range<uint32_t>& r) {
    if (IsCancelled(options)) return;
    std::array<spatial::Neighbor, kMaxK> storage;
    size_t found = 0;
    for (uint32_t slot = r.begin(); slot != r.end(); ++slot) {
      const Eigen::Vector3f p = tree.point(slot);
      const float limit = found == k ? std::min(max_dist_sq, SeedBound(tree, p, std::span(storage.data(), k)))
                                     : max_dist_sq;
      found = tree.Knn(p, limit, std::span(storage.data(), k));
      if (found < kMinK) continue;
      Eigen::Vector3f normal = FitPlaneNormal(tree, std::span(storage.data(), found));
      if (options.orient_towards_viewpoint && normal.dot(options.viewpoint - p) < 0.0f) normal = -normal;
      normals[tree.original_index(slot)] = normal;
    }
  });
  if (IsCancelled(options)) return Cancelled("normals: cancelled");
  return normals;
}

}  // namespace vscan::normals
