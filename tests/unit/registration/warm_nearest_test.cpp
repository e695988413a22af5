#include "registration/warm_nearest.h"

#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vscan::registration {
namespace {

using spatial::KdTree;

float BruteForceNearestSq(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& q) {
  float best = std::numeric_limits<float>::infinity();
  for (const auto& p : points) best = std::min(best, (p - q).squaredNorm());
  return best;
}

TEST(WarmNearestTest, WalkingQueriesMatchBruteForce) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> points(3000);
  for (auto& p : points) p = {u(rng), u(rng), 0.2f * u(rng)};
  const KdTree tree(points);
  const float max_sq = 0.01f * 0.01f;
  int reused = 0;
  for (int walker = 0; walker < 40; ++walker) {
    WarmStart state, neighbour;
    Eigen::Vector3f q(u(rng), u(rng), 0.2f * u(rng));
    for (int step = 0; step < 60; ++step) {
      // Mostly tiny steps (which may keep the old answer), now and then a jump.
      const float size = step % 15 == 14 ? 0.01f : 1e-5f;
      q += size * Eigen::Vector3f(g(rng), g(rng), g(rng));
      const uint32_t before = state.slot;
      const WarmStart* hint = step % 2 == 0 ? &neighbour : nullptr;
      const spatial::Neighbor nb = WarmNearest(tree, q, max_sq, state, hint);
      if (before != KdTree::kNoSlot && state.anchor != q) ++reused;
      const float expected = BruteForceNearestSq(points, q);
      if (expected > max_sq) {
        EXPECT_EQ(nb.slot, KdTree::kNoSlot);
        continue;
      }
      ASSERT_NE(nb.slot, KdTree::kNoSlot) << walker << "/" << step;
      EXPECT_FLOAT_EQ(nb.dist_sq, expected) << walker << "/" << step;
      EXPECT_FLOAT_EQ((tree.point(nb.slot) - q).squaredNorm(), expected);
      WarmStart fresh;
      WarmNearest(tree, q + Eigen::Vector3f::Constant(1e-4f), max_sq, fresh, nullptr);
      neighbour = fresh;
    }
  }
  // Most tiny steps keep the answer without a search.
  EXPECT_GT(reused, 1000);
}

TEST(WarmNearestTest, NothingInReach) {
  const std::vector<Eigen::Vector3f> points{{0, 0, 0}, {1, 0, 0}};
  const KdTree tree(points);
  WarmStart state;
  EXPECT_EQ(WarmNearest(tree, {0.5f, 0.5f, 0.0f}, 0.01f, state, nullptr).slot, KdTree::kNoSlot);
  EXPECT_EQ(state.slot, KdTree::kNoSlot);
  const spatial::Neighbor nb = WarmNearest(tree, {0.95f, 0.0f, 0.0f}, 0.01f, state, nullptr);
  ASSERT_NE(nb.slot, KdTree::kNoSlot);
  EXPECT_EQ(tree.original_index(nb.slot), 1u);
  // The kept answer must still respect the reach once the point has moved away.
  EXPECT_EQ(WarmNearest(tree, {0.95f, 0.2f, 0.0f}, 0.01f, state, nullptr).slot, KdTree::kNoSlot);
}

}  // namespace
}  // namespace vscan::registration
