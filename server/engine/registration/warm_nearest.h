#pragma once
// Nearest-neighbour queries for points that move a little between calls, as ICP's source points
// do: a point that has not moved by half the gap between its nearest and second-nearest
// neighbours keeps its nearest neighbour without a search, and a search that is needed starts
// from a bound that the last one (or a nearby point's) provides.

#include <cstdint>

#include <Eigen/Core>

#include "spatial/kd_tree.h"

namespace vscan::registration {

// What one point's last search found.
struct WarmStart {
  // Where the point was.
  Eigen::Vector3f anchor = Eigen::Vector3f::Zero();
  // Its distance to the second-nearest point then, or a lower bound of it.
  float second = 0.0f;
  // Its nearest point then, kNoSlot before any search or when none was in reach.
  uint32_t slot = spatial::KdTree::kNoSlot;
};

// The nearest point of `tree` to q within sqrt(max_dist_sq), exactly as KdTree::Nearest finds it
// (ties aside), updating `state`. `hint`, when not null, is the state of another point close by,
// which bounds the search for a point without a usable state of its own.
spatial::Neighbor WarmNearest(const spatial::KdTree& tree, const Eigen::Vector3f& q, float max_dist_sq,
                              WarmStart& state, const WarmStart* hint);

}  // namespace vscan::registration
