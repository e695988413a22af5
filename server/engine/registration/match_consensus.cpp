#include "registration/match_consensus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "random/seeded_draws.h"

namespace vscan::registration {
namespace {

// Draws of a partner that agrees with the pairs drawn so far before the hypothesis is given up.
constexpr int kPartnerDraws = 64;
// The pairs of a hypothesis lie at least this many inlier distances apart, and each corner of
// their triangle at least half that from the opposite side, so that noise hardly turns it.
constexpr float kMinSpread = 3.0f;
// Rounds of refitting to all inliers of the best hypothesis.
constexpr int kRefits = 10;
// Hypotheses drawn, then scored in parallel, between polls of cancel.
constexpr int kConsensusBatch = 1024;

class Sampler {
 public:
  Sampler(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> target, float inlier_distance,
          uint64_t seed)
      : source_(source),
        target_(target),
        tolerance_(inlier_distance),
        min_edge_(kMinSpread * inlier_distance),
        draws_(seed) {}

  // Three pairs that agree with each other, or false when the draws ran out.
  bool Draw(std::array<size_t, 3>& picked) {
    picked[0] = Index();
    return DrawUntil(picked[1], [&](size_t j) { return Agree(picked[0], j); }) && DrawUntil(picked[2], [&](size_t k) {
             return Agree(picked[0], k) && Agree(picked[1], k) && WellShaped(picked[0], picked[1], k);
           });
  }

 private:
  size_t Index() { return static_cast<size_t>(draws_.Uniform() * static_cast<double>(source_.size())); }

  template <class Accept>
  bool DrawUntil(size_t& out, Accept accept) {
    for (int tries = 0; tries < kPartnerDraws; ++tries) {
      out = Index();
      if (accept(out)) return true;
    }
    return false;
  }

  // Both clouds see the two pairs about as far apart, and far enough apart to fix a direction.
  bool Agree(size_t a, size_t b) const {
    const float in_source = (source_[a] - source_[b]).norm();
    const float in_target = (target_[a] - target_[b]).norm();
    return in_source >= min_edge_ && std::abs(in_source - in_target) <= tolerance_;
  }

  bool WellShaped(size_t a, size_t b, size_t c) const {
    const Eigen::Vector3f ab = source_[b] - source_[a], ac = source_[c] - source_[a];
    const float longest = std::max({ab.norm(), ac.norm(), (ac - ab).norm()});
    return ab.cross(ac).norm() / longest >= 0.5f * min_edge_;
  }

  std::span<const Eigen::Vector3f> source_, target_;
  float tolerance_, min_edge_;
  random::SplitMix64Stream draws_;
};

Pose3 Fit(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> target,
          std::span<const size_t> chosen) {
  Eigen::Matrix3Xd from(3, chosen.size()), to(3, chosen.size());
  for (size_t c = 0; c < chosen.size(); ++c) {
    from.col(static_cast<Eigen::Index>(c)) = source[chosen[c]].cast<double>();
    to.col(static_cast<Eigen::Index>(c)) = target[chosen[c]].cast<double>();
  }
  return Pose3(Eigen::umeyama(from, to, false));
}

size_t CountInliers(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> target, const Pose3& pose,
                    float inlier_distance, std::vector<size_t>* inliers = nullptr) {
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const Eigen::Vector3f translation = pose.translation().cast<float>();
  const float limit_sq = inlier_distance * inlier_distance;
  size_t count = 0;
  if (inliers != nullptr) inliers->clear();
  for (size_t i = 0; i < source.size(); ++i) {
    if ((rotation * source[i] + translation - target[i]).squaredNorm() > limit_sq) continue;
    ++count;
    if (inliers != nullptr) inliers->push_back(i);
  }
  return count;
}

}  // namespace

StatusOr<Consensus> FindMatchConsensus(std::span<const Eigen::Vector3f> source, std::span<const Eigen::Vector3f> target,
                                       const ConsensusOptions& options) {
  if (source.size() != target.size()) return InvalidArgument("matches: one target point per source point");
  Consensus best;
  if (source.size() < 3) return best;
  const auto inlier_distance = static_cast<float>(options.inlier_distance);
  Sampler sampler(source, target, inlier_distance, options.seed);
  // Hypotheses are drawn in order and scored in parallel; the first of the best wins, so the result
  // does not depend on the thread count.
  std::vector<std::array<size_t, 3>> drawn;
  std::vector<Pose3> poses;
  std::vector<size_t> counts;
  for (int begin = 0; begin < options.iterations; begin += kConsensusBatch) {
    if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) {
      return Cancelled("features: cancelled");
    }
    drawn.clear();
    std::array<size_t, 3> picked{};
    for (int iteration = begin; iteration < std::min(options.iterations, begin + kConsensusBatch); ++iteration) {
      if (sampler.Draw(picked)) drawn.push_back(picked);
    }
    poses.resize(drawn.size());
    counts.resize(drawn.size());
    tbb::parallel_for(size_t{0}, drawn.size(), [&](size_t h) {
      poses[h] = Fit(source, target, drawn[h]);
      counts[h] = CountInliers(source, target, poses[h], inlier_distance);
    });
    for (size_t h = 0; h < drawn.size(); ++h) {
      if (counts[h] > best.inliers) best = {poses[h], counts[h]};
    }
  }
  if (best.inliers < 3) return best;
  // The least-squares fit to all inliers is the better estimate even when it keeps fewer of them
  // (chance inliers of the three-pair hypothesis drop out).
  std::vector<size_t> chosen, next;
  CountInliers(source, target, best.target_from_source, inlier_distance, &chosen);
  for (int round = 0; round < kRefits; ++round) {
    const Pose3 pose = Fit(source, target, chosen);
    if (CountInliers(source, target, pose, inlier_distance, &next) < 3) break;
    best = {pose, next.size()};
    if (next == chosen) break;
    std::swap(chosen, next);
  }
  return best;
}

}  // namespace vscan::registration
