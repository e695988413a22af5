#include "evaluation/distance_summary.h"

#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace vscan::evaluation {

DistanceSummary Summarize(std::span<const float> distances, double tau) {
  DistanceSummary s;
  if (distances.empty()) return s;
  struct Sums {
    double total = 0;
    size_t within = 0;
  };
  const Sums sums = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, distances.size(), 8192), Sums{},
      [&](const tbb::blocked_range<size_t>& r, Sums acc) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          acc.total += distances[i];
          acc.within += distances[i] <= tau ? 1 : 0;
        }
        return acc;
      },
      [](Sums a, const Sums& b) {
        a.total += b.total;
        a.within += b.within;
        return a;
      });
  const double n = static_cast<double>(distances.size());
  s.mean = sums.total / n;
  s.within_tau = static_cast<double>(sums.within) / n;
  std::vector<float> sorted(distances.begin(), distances.end());
  const size_t mid = sorted.size() / 2;
  std::nth_element(sorted.begin(), sorted.begin() + mid, sorted.end());
  s.median = sorted[mid];
  if (sorted.size() % 2 == 0) {
    s.median = 0.5 * (s.median + *std::max_element(sorted.begin(), sorted.begin() + mid));
  }
  return s;
}

}  // namespace vscan::evaluation
