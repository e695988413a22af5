#include "reconstruction/union_cloud.h"

#include <cmath>
#include <cstdint>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace vscan::reconstruction {
namespace {

struct Entry {
  uint64_t key;
  uint32_t scan;
  uint32_t index;
  bool operator<(const Entry& o) const {
    return key != o.key ? key < o.key : scan != o.scan ? scan < o.scan : index < o.index;
  }
};

// 21 bits per axis around the origin; points beyond that range are dropped.
bool VoxelKey(const Eigen::Vector3f& p, float inv_voxel, uint64_t& key) {
  constexpr int64_t kHalf = int64_t{1} << 20;
  uint64_t k = 0;
  for (int a = 0; a < 3; ++a) {
    const float c = std::floor(p[a] * inv_voxel);
    if (!(c >= -kHalf && c < kHalf)) return false;
    k |= static_cast<uint64_t>(static_cast<int64_t>(c) + kHalf) << (21 * a);
  }
  key = k;
  return true;
}

}  // namespace

UnionCloud VoxelDownsample(std::span<const ScanPoints> scans, float voxel_size) {
  const float inv_voxel = 1.0f / voxel_size;
  std::vector<Entry> entries;
  for (uint32_t s = 0; s < scans.size(); ++s) {
    for (uint32_t i = 0; i < scans[s].points.size(); ++i) {
      uint64_t key;
      if (scans[s].points[i].allFinite() && VoxelKey(scans[s].points[i], inv_voxel, key)) entries.push_back({key, s, i});
    }
  }
  tbb::parallel_sort(entries.begin(), entries.end());
  std::vector<size_t> starts;
  for (size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].key != entries[i - 1].key) starts.push_back(i);
  }
  starts.push_back(entries.size());
  UnionCloud out;
  const size_t n = starts.size() - 1;
  out.positions.resize(n);
  out.view_directions.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      Eigen::Vector3f view = Eigen::Vector3f::Zero();
      for (size_t i = starts[v]; i < starts[v + 1]; ++i) {
        const ScanPoints& scan = scans[entries[i].scan];
        const Eigen::Vector3f& p = scan.points[entries[i].index];
        sum += p.cast<double>();
        view += (scan.sensor_origin - p).normalized();
      }
      out.positions[v] = (sum / static_cast<double>(starts[v + 1] - starts[v])).cast<float>();
      out.view_directions[v] = view.normalized();
    }
  });
  return out;
}

}  // namespace vscan::reconstruction
