#include "registration/warm_nearest.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vscan::registration {
namespace {

using spatial::KdTree;

// Float rounding of the distances involved, relative to the coordinates' magnitude, with margin.
float Slack(const Eigen::Vector3f& q) { return 1e-6f * q.cwiseAbs().maxCoeff(); }

}  // namespace

spatial::Neighbor WarmNearest(const KdTree& tree, const Eigen::Vector3f& q, float max_dist_sq, WarmStart& state,
                              const WarmStart* hint) {
  const float slack = Slack(q);
  float bound_sq = max_dist_sq;
  if (state.slot != KdTree::kNoSlot) {
    const float moved = (q - state.anchor).norm();
    const float nearest = (tree.point(state.slot) - state.anchor).norm();
    // Every other point was at least `second` from the anchor, so at least second - moved from q,
    // while the old nearest is at most nearest + moved from q.
    if (2.0f * moved + slack < state.second - nearest) {
      const float dist_sq = (tree.point(state.slot) - q).squaredNorm();
      if (dist_sq <= max_dist_sq) return {dist_sq, state.slot};
      return {max_dist_sq, KdTree::kNoSlot};
    }
    // What the last search found lies within second + moved of q.
    bound_sq = std::min(bound_sq, (state.second + moved + slack) * (state.second + moved + slack));
  } else if (hint != nullptr && hint->slot != KdTree::kNoSlot) {
    const float reach = hint->second + (q - hint->anchor).norm() + slack;
    bound_sq = std::min(bound_sq, reach * reach);
  }
  const std::array<spatial::Neighbor, 2> found = tree.NearestTwo(q, bound_sq);
  if (found[0].slot == KdTree::kNoSlot) {
    state.slot = KdTree::kNoSlot;
    return {max_dist_sq, KdTree::kNoSlot};
  }
  // With one point found, the second lies beyond the bound, which is then its distance.
  state = {q, std::sqrt(found[1].dist_sq), found[0].slot};
  return found[0];
}

}  // namespace vscan::registration
