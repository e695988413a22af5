#include "localization/pose_matching.h"

#include <algorithm>
#include <numeric>

namespace vscan::localization {

std::vector<int> MatchEstimates(std::span<const double> scores, const Eigen::MatrixXd& errors,
                                std::span<const bool> valid, double threshold, size_t max_estimates) {
  std::vector<size_t> order(scores.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scores[a] > scores[b]; });
  if (max_estimates > 0 && order.size() > max_estimates) order.resize(max_estimates);

  const auto truths = static_cast<size_t>(errors.cols());
  std::vector<int> match(truths, kUnmatched);
  for (const size_t e : order) {
    int best = kUnmatched;
    double best_error = threshold;
    for (size_t g = 0; g < truths; ++g) {
      if (!valid[g] || match[g] != kUnmatched) continue;
      const double error = errors(static_cast<Eigen::Index>(e), static_cast<Eigen::Index>(g));
      if (error < best_error) {
        best = static_cast<int>(g);
        best_error = error;
      }
    }
    if (best != kUnmatched) match[static_cast<size_t>(best)] = static_cast<int>(e);
  }
  return match;
}

}  // namespace vscan::localization
