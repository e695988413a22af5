#include "registration/spatial_order.h"

#include <algorithm>
#include <limits>
#include <utility>

#include <tbb/parallel_sort.h>

namespace vscan::registration {
namespace {

constexpr uint32_t kBits = 21;

// Spreads the low 21 bits of v so that two zero bits separate each.
uint64_t Spread(uint64_t v) {
  v &= (1ull << kBits) - 1;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

}  // namespace

std::vector<uint32_t> MortonOrder(std::span<const Eigen::Vector3f> points) {
  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Array3f hi = -lo;
  for (const Eigen::Vector3f& p : points) {
    if (!p.allFinite()) continue;
    lo = lo.min(p.array());
    hi = hi.max(p.array());
  }
  std::vector<std::pair<uint64_t, uint32_t>> keyed;
  keyed.reserve(points.size());
  const float cells = static_cast<float>((1u << kBits) - 1);
  const Eigen::Array3f scale = cells / (hi - lo).max(std::numeric_limits<float>::min());
  for (uint32_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    const Eigen::Array3f cell = ((points[i].array() - lo) * scale).min(cells).max(0.0f);
    const uint64_t code = Spread(static_cast<uint64_t>(cell.x())) | Spread(static_cast<uint64_t>(cell.y())) << 1 |
                          Spread(static_cast<uint64_t>(cell.z())) << 2;
    keyed.emplace_back(code, i);
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<uint32_t> order(keyed.size());
  for (size_t k = 0; k < keyed.size(); ++k) order[k] = keyed[k].second;
  return order;
}

}  // namespace vscan::registration
