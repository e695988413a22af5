#pragma once
// Mean, median and the share within a threshold of a list of distances.

#include <span>

namespace vscan::evaluation {

struct DistanceSummary {
  double mean = 0;
  double median = 0;
  // Share of the distances that are <= tau, in [0, 1]; 0 for an empty list.
  double within_tau = 0;
};

// Infinite distances (nothing found) count as beyond tau and make the mean infinite.
DistanceSummary Summarize(std::span<const float> distances, double tau);

}  // namespace vscan::evaluation
