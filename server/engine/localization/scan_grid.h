#pragma once
// The scan's points by cell of a uniform grid, for gathering the points around a placed part
// without visiting the whole scan.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace vscan::localization {

class ScanGrid {
 public:
  // cell (metres, > 0) should be at least the farthest distance a query asks about.
  ScanGrid(std::span<const Eigen::Vector3f> points, double cell);

  // The indices of the points in the cells within one cell of any of `around` (so every point
  // within `cell` of one of them, and some farther), each once, in no particular order.
  void Gather(std::span<const Eigen::Vector3f> around, std::vector<uint32_t>& out) const;

 private:
  uint64_t Key(int64_t x, int64_t y, int64_t z) const;

  double inverse_cell_;
  std::vector<uint32_t> order_;  // point indices grouped by cell
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> cells_;  // cell key -> run in order_
};

}  // namespace vscan::localization
