#include "registration/descriptor_matching.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_for.h>

namespace vscan::registration {
namespace {

// Source columns per block: one block's distances to all targets is a matrix product.
constexpr Eigen::Index kBlock = 256;

struct Nearest {
  float dist_sq = std::numeric_limits<float>::infinity();
  uint32_t column = 0;
};

void Keep(Nearest& best, float dist_sq, uint32_t column) {
  if (dist_sq < best.dist_sq || (dist_sq == best.dist_sq && column < best.column)) best = {dist_sq, column};
}

}  // namespace

StatusOr<std::vector<DescriptorMatch>> MatchMutualNearest(const Eigen::MatrixXf& source, const Eigen::MatrixXf& target,
                                                          const std::atomic<bool>* cancel) {
  if (source.rows() != target.rows()) return InvalidArgument("descriptors: lengths differ");
  const Eigen::Index n_source = source.cols(), n_target = target.cols();
  if (n_source == 0 || n_target == 0) return std::vector<DescriptorMatch>{};
  const Eigen::RowVectorXf target_sq = target.colwise().squaredNorm();
  const Eigen::Index blocks = (n_source + kBlock - 1) / kBlock;
  std::vector<Nearest> source_nearest(static_cast<size_t>(n_source));
  // Per block, each target's nearest source within the block; merged in block order below.
  std::vector<Nearest> target_nearest(static_cast<size_t>(blocks * n_target));
  std::atomic<bool> cancelled = false;
  tbb::parallel_for(Eigen::Index{0}, blocks, [&](Eigen::Index block) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
      cancelled = true;
      return;
    }
    const Eigen::Index begin = block * kBlock, count = std::min(kBlock, n_source - begin);
    const auto sources = source.middleCols(begin, count);
    // |s - t|^2 = |s|^2 + |t|^2 - 2 s.t, one row per source column.
    Eigen::MatrixXf dist_sq = -2.0f * (sources.transpose() * target);
    dist_sq.colwise() += sources.colwise().squaredNorm().transpose();
    dist_sq.rowwise() += target_sq;
    Nearest* per_target = &target_nearest[static_cast<size_t>(block * n_target)];
    for (Eigen::Index t = 0; t < n_target; ++t) {
      for (Eigen::Index s = 0; s < count; ++s) {
        Keep(per_target[t], dist_sq(s, t), static_cast<uint32_t>(begin + s));
        Keep(source_nearest[static_cast<size_t>(begin + s)], dist_sq(s, t), static_cast<uint32_t>(t));
      }
    }
  });
  if (cancelled) return Cancelled("features: cancelled");
  std::vector<Nearest> target_best(static_cast<size_t>(n_target));
  for (Eigen::Index block = 0; block < blocks; ++block) {
    for (Eigen::Index t = 0; t < n_target; ++t) {
      const Nearest& candidate = target_nearest[static_cast<size_t>(block * n_target + t)];
      Keep(target_best[static_cast<size_t>(t)], candidate.dist_sq, candidate.column);
    }
  }
  std::vector<DescriptorMatch> matches;
  for (Eigen::Index s = 0; s < n_source; ++s) {
    const uint32_t t = source_nearest[static_cast<size_t>(s)].column;
    if (target_best[t].column == static_cast<uint32_t>(s)) matches.push_back({static_cast<uint32_t>(s), t});
  }
  return matches;
}

}  // namespace vscan::registration
