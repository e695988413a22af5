#include <gtest/gtest.h>

#include "capture/pixel_draws.h"
#include "random/seeded_draws.h"

namespace vscan::random {
namespace {

// The bits below are what the per-module copies of SplitMix64 gave before they became one; a
// change here changes every seeded scan, IK restart and campaign step seed.
TEST(SeededDrawsTest, SplitMix64GivesTheReferenceBits) {
  EXPECT_EQ(SplitMix64(0), 0xe220a8397b1dcdafull);
  EXPECT_EQ(SplitMix64(42), 0xbdd732262feb6e95ull);
  EXPECT_EQ(SplitMix64(99 ^ SplitMix64(3)), 0x9516e9ca100c6501ull);  // campaign step 3 of seed 99
}

TEST(SeededDrawsTest, StreamMatchesTheSequentialGenerator) {
  SplitMix64Stream stream(5);
  EXPECT_EQ(stream.NextBits(), 0x63033b0ca389c35aull);
  EXPECT_EQ(stream.NextBits(), 0xc097314d939736f8ull);
  EXPECT_EQ(stream.NextBits(), 0x3b92d3f0106bc147ull);
}

TEST(SeededDrawsTest, PixelDrawsKeepTheirBits) {
  capture::PixelDraws draws(7, capture::DrawStream::kFlyingPixel, 1234);
  EXPECT_EQ(draws.Uniform(), UnitInterval(0xd61ebfbd427a38c9ull));
  EXPECT_EQ(draws.Uniform(), UnitInterval(0xecdd5676f47f58d0ull));
  EXPECT_EQ(draws.Uniform(), UnitInterval(0x2673715d3220332bull));
}

TEST(SeededDrawsTest, UnitIntervalsHaveTheirEnds) {
  EXPECT_EQ(UnitInterval(0), 0.0);
  EXPECT_LT(UnitInterval(~0ull), 1.0);
  EXPECT_GT(UnitIntervalAboveZero(0), 0.0);
  EXPECT_EQ(UnitIntervalAboveZero(~0ull), 1.0);
}

}  // namespace
}  // namespace vscan::random
