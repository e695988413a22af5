#include "evaluation/greedy_cover.h"

#include <vector>

#include <gtest/gtest.h>

namespace vscan::evaluation {
namespace {

SampleBits Bits(size_t size, std::initializer_list<size_t> members) {
  SampleBits bits(size);
  for (const size_t i : members) bits.Set(i);
  return bits;
}

TEST(SampleBits, CountsAcrossWordBoundaries) {
  const SampleBits a = Bits(200, {0, 63, 64, 129, 199});
  const SampleBits b = Bits(200, {63, 129, 150});
  EXPECT_EQ(a.Count(), 5u);
  EXPECT_TRUE(a.Test(64));
  EXPECT_FALSE(a.Test(65));
  EXPECT_EQ(a.CountNotIn(b), 3u);
  EXPECT_EQ(b.CountNotIn(a), 1u);
  SampleBits both = a;
  both.Add(b);
  EXPECT_EQ(both.Count(), 6u);
  EXPECT_TRUE(both.Test(150));
}

// A = {0..5} first (6 new), then D = {6, 7} adds 2 where B and C add 1 each.
std::vector<SampleBits> Sets() {
  return {Bits(8, {0, 1, 2, 3, 4, 5}), Bits(8, {0, 1, 2, 6}), Bits(8, {3, 4, 5, 7}), Bits(8, {6, 7})};
}

TEST(GreedyMaxCoverage, PicksTheLargestGainEachRound) {
  const std::vector<SampleBits> sets = Sets();
  const auto picks = GreedyMaxCoverage(sets, 8, 10, 1);
  ASSERT_EQ(picks.size(), 2u);
  EXPECT_EQ(picks[0].set, 0u);
  EXPECT_EQ(picks[0].gain, 6u);
  EXPECT_EQ(picks[1].set, 3u);
  EXPECT_EQ(picks[1].gain, 2u);
}

TEST(GreedyMaxCoverage, StopsAtMaxPicksAndBelowTheMinimumGain) {
  const std::vector<SampleBits> sets = Sets();
  EXPECT_EQ(GreedyMaxCoverage(sets, 8, 1, 1).size(), 1u);
  EXPECT_EQ(GreedyMaxCoverage(sets, 8, 10, 3).size(), 1u);
  EXPECT_TRUE(GreedyMaxCoverage(sets, 8, 10, 7).empty());
  EXPECT_TRUE(GreedyMaxCoverage(sets, 8, 0, 1).empty());
}

TEST(GreedyMaxCoverage, BreaksTiesTowardsTheLowerIndex) {
  const std::vector<SampleBits> sets = {Bits(4, {2}), Bits(4, {0, 1}), Bits(4, {2, 3})};
  const auto picks = GreedyMaxCoverage(sets, 4, 10, 1);
  ASSERT_EQ(picks.size(), 2u);
  EXPECT_EQ(picks[0].set, 1u);
  EXPECT_EQ(picks[1].set, 2u);
}

}  // namespace
}  // namespace vscan::evaluation
