#pragma once
// Seeded RANSAC over matched point pairs: the rigid transform most pairs agree with.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::registration {

struct ConsensusOptions {
  int iterations = 20000;
  // A pair is an inlier when the transformed source point lies within this of its target (metres).
  double inlier_distance = 0.006;
  uint64_t seed = 1;
  const std::atomic<bool>* cancel = nullptr;
};

struct Consensus {
  // Fitted to all inliers of the best hypothesis.
  Pose3 target_from_source = Pose3::Identity();
  // 0 when no hypothesis could be drawn (too few pairs, or none spread enough).
  size_t inliers = 0;
};

// source[i] is matched to target[i]. Each hypothesis is three pairs whose mutual distances agree
// in both clouds (the second and third are drawn among the pairs that agree with the first, which
// keeps the odds of an all-inlier sample high when most matches are wrong), fitted by Umeyama's
// method and scored by its inliers. The same inputs and seed give the same result.
// Cancelled when cancel becomes true.
StatusOr<Consensus> FindMatchConsensus(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> target,
                                       const ConsensusOptions& options);

}  // namespace vscan::registration
