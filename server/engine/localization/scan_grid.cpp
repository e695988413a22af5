#include "localization/scan_grid.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vscan::localization {
namespace {

constexpr int64_t kBias = int64_t{1} << 20;

}  // namespace

uint64_t ScanGrid::Key(int64_t x, int64_t y, int64_t z) const {
  const auto field = [](int64_t v) { return static_cast<uint64_t>(std::clamp<int64_t>(v + kBias, 0, 2 * kBias - 1)); };
  return (field(x) << 42) | (field(y) << 21) | field(z);
}

ScanGrid::ScanGrid(std::span<const Eigen::Vector3f> points, double cell) : inverse_cell_(1.0 / cell) {
  std::vector<std::pair<uint64_t, uint32_t>> keyed;
  keyed.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    const Eigen::Vector3d c = (points[i].cast<double>() * inverse_cell_).array().floor();
    keyed.emplace_back(Key(static_cast<int64_t>(c.x()), static_cast<int64_t>(c.y()), static_cast<int64_t>(c.z())),
                       static_cast<uint32_t>(i));
  }
  std::sort(keyed.begin(), keyed.end());
  order_.reserve(keyed.size());
  for (size_t begin = 0; begin < keyed.size();) {
    size_t end = begin + 1;
    while (end < keyed.size() && keyed[end].first == keyed[begin].first) ++end;
    cells_.emplace(keyed[begin].first, std::make_pair(static_cast<uint32_t>(begin), static_cast<uint32_t>(end)));
    begin = end;
  }
  for (const auto& [key, index] : keyed) order_.push_back(index);
}

void ScanGrid::Gather(std::span<const Eigen::Vector3f> around, std::vector<uint32_t>& out) const {
  // The cells the points fall in first (several points share one), then their neighbours.
  std::vector<std::array<int64_t, 3>> centres;
  centres.reserve(around.size());
  for (const auto& p : around) {
    if (!p.allFinite()) continue;
    const Eigen::Vector3d c = (p.cast<double>() * inverse_cell_).array().floor();
    centres.push_back({static_cast<int64_t>(c.x()), static_cast<int64_t>(c.y()), static_cast<int64_t>(c.z())});
  }
  std::sort(centres.begin(), centres.end());
  centres.erase(std::unique(centres.begin(), centres.end()), centres.end());
  std::vector<uint64_t> keys;
  keys.reserve(centres.size() * 27);
  for (const auto& c : centres) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) keys.push_back(Key(c[0] + dx, c[1] + dy, c[2] + dz));
      }
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  for (const uint64_t key : keys) {
    const auto cell = cells_.find(key);
    if (cell == cells_.end()) continue;
    out.insert(out.end(), order_.begin() + cell->second.first, order_.begin() + cell->second.second);
  }
}

}  // namespace vscan::localization
