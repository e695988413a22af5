#pragma once
// BOP's greedy matching of estimated poses to true poses of one part in one scan
// (bop_toolkit_lib/pose_matching.py, match_poses).

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::localization {

inline constexpr int kUnmatched = -1;

// errors(p, g): the error of estimate p against true instance g. Estimates are taken by decreasing
// score (ties in input order), only the first max_estimates of them (0: all); each takes, among the
// valid true instances not matched yet, the one with the lowest error, if that error is below
// threshold. Returns, per true instance, the index of its estimate or kUnmatched.
std::vector<int> MatchEstimates(std::span<const double> scores, const Eigen::MatrixXd& errors,
                                std::span<const bool> valid, double threshold, size_t max_estimates);

}  // namespace vscan::localization
