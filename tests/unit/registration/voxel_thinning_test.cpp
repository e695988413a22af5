#include "registration/voxel_thinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "registration/voxel_union.h"

namespace vscan::registration {
namespace {

using V = Eigen::Vector3f;

TEST(VoxelThinningTest, OneCentroidPerOccupiedVoxelWhateverTheInputOrder) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Values that are exact in binary, so the centroids are exact whatever the order of the sums.
  std::vector<V> points = {V(0.125f, 0.25f, 0.5f),  V(0.375f, 0.75f, 0.5f), V(1.5f, 0.5f, 0.5f),
                           V(-0.5f, 0.25f, 0.75f), V(-0.25f, 0.75f, 0.25f), V(nan, 0.0f, 0.0f),
                           V(0.5f, 0.5f, 2.5f)};
  const std::vector<V> thinned = ThinToVoxelCentroids(points, 1.0);
  ASSERT_EQ(thinned.size(), 4u);
  const auto contains = [&](const V& c) { return std::find(thinned.begin(), thinned.end(), c) != thinned.end(); };
  EXPECT_TRUE(contains(V(0.25f, 0.5f, 0.5f)));
  EXPECT_TRUE(contains(V(1.5f, 0.5f, 0.5f)));
  EXPECT_TRUE(contains(V(-0.375f, 0.5f, 0.5f)));
  EXPECT_TRUE(contains(V(0.5f, 0.5f, 2.5f)));
  std::mt19937 rng(4);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(points.begin(), points.end(), rng);
    EXPECT_EQ(ThinToVoxelCentroids(points, 1.0), thinned);
  }
}

TEST(VoxelThinningTest, PointsWithoutAKeyAreDropped) {
  const std::vector<V> points = {V(0.0f, 0.0f, 0.0f), V(3e3f, 0.0f, 0.0f), V(0.0f, -3e3f, 0.0f)};
  // 2^20 voxels of 2 mm reach about 2.1 km.
  EXPECT_EQ(ThinToVoxelCentroids(points, 0.002).size(), 1u);
  EXPECT_FALSE(VoxelKey(V(3e3f, 0.0f, 0.0f), 500.0).has_value());
  EXPECT_TRUE(VoxelKey(V(2e3f, -2e3f, 0.0f), 500.0).has_value());
  EXPECT_NE(VoxelKey(V(0.001f, 0.0f, 0.0f), 500.0), VoxelKey(V(-0.001f, 0.0f, 0.0f), 500.0));
}

TEST(VoxelUnionTest, MergesPointsAndNormalsPerVoxel) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  VoxelUnion merged(1.0);
  const V up(0.0f, 0.0f, 1.0f), tilted = V(1.0f, 0.0f, 1.0f).normalized();
  merged.Add(std::vector<V>{V(0.25f, 0.5f, 0.5f), V(2.5f, 0.5f, 0.5f), V(5.5f, 0.5f, 0.5f)},
             std::vector<V>{up, up, V(nan, nan, nan)});
  merged.Add(std::vector<V>{V(0.75f, 0.5f, 0.5f), V(2.5f, 0.5f, 0.5f), V(5.5f, 0.5f, 0.5f)},
             std::vector<V>{tilted, -up, up});
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged.points()[0], V(0.5f, 0.5f, 0.5f));
  EXPECT_LT((merged.normals()[0] - (up + tilted).normalized()).norm(), 1e-6f);
  // Opposite normals in one voxel (the two sides of a thin wall) give none.
  EXPECT_FALSE(merged.normals()[1].allFinite());
  // A missing normal adds the position only.
  EXPECT_EQ(merged.normals()[2], up);
  merged.Clear();
  EXPECT_EQ(merged.size(), 0u);
}

}  // namespace
}  // namespace vscan::registration
