#include "registration/voxel_thinning.h"

#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace vscan::registration {
namespace {

constexpr int kKeyBits = 21;
constexpr int64_t kKeyOffset = int64_t{1} << (kKeyBits - 1);
constexpr uint64_t kNoKey = ~uint64_t{0};

struct KeyedPoint {
  uint64_t key;
  uint32_t index;
};

}  // namespace

std::optional<uint64_t> VoxelKey(const Eigen::Vector3f& point, double inverse_voxel_size) {
  uint64_t key = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double cell = std::floor(static_cast<double>(point[axis]) * inverse_voxel_size);
    // Also false for NaN.
    if (!(cell >= -static_cast<double>(kKeyOffset) && cell < static_cast<double>(kKeyOffset))) return std::nullopt;
    key |= static_cast<uint64_t>(static_cast<int64_t>(cell) + kKeyOffset) << (kKeyBits * axis);
  }
  return key;
}

std::vector<Eigen::Vector3f> ThinToVoxelCentroids(std::span<const Eigen::Vector3f> points, double voxel_size) {
  const double inverse = 1.0 / voxel_size;
  std::vector<KeyedPoint> keyed(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size()), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      keyed[i] = {VoxelKey(points[i], inverse).value_or(kNoKey), static_cast<uint32_t>(i)};
    }
  });
  // Keys and indices together are unique, so the sorted order does not depend on the schedule.
  tbb::parallel_sort(keyed.begin(), keyed.end(), [](const KeyedPoint& a, const KeyedPoint& b) {
    return a.key != b.key ? a.key < b.key : a.index < b.index;
  });
  while (!keyed.empty() && keyed.back().key == kNoKey) keyed.pop_back();

  std::vector<size_t> run_starts;
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].key != keyed[i - 1].key) run_starts.push_back(i);
  }
  run_starts.push_back(keyed.size());
  std::vector<Eigen::Vector3f> centroids(run_starts.size() - 1);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, centroids.size()), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (size_t k = run_starts[v]; k != run_starts[v + 1]; ++k) sum += points[keyed[k].index].cast<double>();
      centroids[v] = (sum / static_cast<double>(run_starts[v + 1] - run_starts[v])).cast<float>();
    }
  });
  return centroids;
}

}  // namespace vscan::registration
