#pragma once
// Matches between two sets of descriptors by nearest neighbour in descriptor space.

#include <atomic>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::registration {

struct DescriptorMatch {
  uint32_t source;  // column of the source descriptors
  uint32_t target;  // column of the target descriptors
};

// Mutual nearest neighbours: each source column whose nearest target column (Euclidean) has that
// source column as its own nearest, in source order. Columns are descriptors of equal length.
// Exact (every pair is compared, parallel with TBB); ties go to the lower column, so the answer
// does not depend on the thread count. Cancelled when cancel becomes true.
StatusOr<std::vector<DescriptorMatch>> MatchMutualNearest(const Eigen::MatrixXf& source, const Eigen::MatrixXf& target,
                                                          const std::atomic<bool>* cancel);

}  // namespace vscan::registration
