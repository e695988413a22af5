#include "registration/scan_overlap.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "registration/voxel_thinning.h"

namespace vscan::registration {
namespace {

std::vector<uint64_t> OccupiedCells(std::span<const Eigen::Vector3f> points, double cell_size) {
  std::vector<uint64_t> cells;
  cells.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    if (const auto key = VoxelKey(p, 1.0 / cell_size)) cells.push_back(*key);
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

size_t SharedCount(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) {
  size_t shared = 0;
  auto i = a.begin(), j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (*i < *j) {
      ++i;
    } else if (*j < *i) {
      ++j;
    } else {
      ++shared;
      ++i;
      ++j;
    }
  }
  return shared;
}

}  // namespace

std::vector<std::pair<size_t, size_t>> CandidatePairs(std::span<const std::vector<Eigen::Vector3f>> clouds,
                                                      double cell_size, size_t per_cloud) {
  const size_t n = clouds.size();
  std::vector<std::vector<uint64_t>> cells(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) { cells[i] = OccupiedCells(clouds[i], cell_size); });
  std::vector<std::vector<size_t>> best(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    std::vector<std::pair<size_t, size_t>> ranked;  // (shared cells, other)
    for (size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const size_t shared = SharedCount(cells[i], cells[j]);
      if (shared > 0) ranked.emplace_back(shared, j);
    }
    std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    for (size_t k = 0; k < std::min(per_cloud, ranked.size()); ++k) best[i].push_back(ranked[k].second);
  });
  std::vector<std::pair<size_t, size_t>> pairs;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j : best[i]) pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

double OverlapShare(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> source_normals,
                    const TargetIndex& target, double reach, double max_normal_angle, size_t max_samples) {
  if (source.empty() || target.size() == 0 || max_samples == 0) return 0.0;
  const size_t stride = std::max<size_t>(1, source.size() / max_samples);
  const auto reach_sq = static_cast<float>(reach * reach);
  const float min_cos = static_cast<float>(std::cos(max_normal_angle));
  size_t sampled = 0, within = 0;
  for (size_t i = stride / 2; i < source.size(); i += stride) {
    ++sampled;
    const spatial::Neighbor nb = target.tree().NearestTwo(source[i], reach_sq)[0];
    if (nb.slot != spatial::KdTree::kNoSlot && std::abs(target.normal(nb.slot).dot(source_normals[i])) >= min_cos) {
      ++within;
    }
  }
  return static_cast<double>(within) / static_cast<double>(sampled);
}

}  // namespace vscan::registration
