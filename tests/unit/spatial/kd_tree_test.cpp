#include "spatial/kd_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace vscan::spatial {
namespace {

std::vector<Eigen::Vector3f> RandomPoints(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Eigen::Vector3f> points(n);
  for (auto& p : points) p = {u(rng), u(rng), 0.2f * u(rng)};
  return points;
}

// Squared distances of the k nearest points within the limit, ascending.
std::vector<float> BruteForce(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& q,
                              size_t k, float max_dist_sq) {
  std::vector<float> d;
  for (const auto& p : points) {
    const float d2 = (p - q).squaredNorm();
    if (d2 <= max_dist_sq) d.push_back(d2);
  }
  std::sort(d.begin(), d.end());
  d.resize(std::min(d.size(), k));
  return d;
}

void ExpectMatchesBruteForce(const std::vector<Eigen::Vector3f>& points, size_t k, float max_dist_sq) {
  const KdTree tree(points);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  std::vector<Neighbor> out(k);
  for (int i = 0; i < 300; ++i) {
    // Half the queries are cloud points (the self match must come first), half are anywhere.
    const Eigen::Vector3f q = i % 2 == 0 ? points[static_cast<size_t>(i) * 7 % points.size()]
                                         : Eigen::Vector3f(u(rng), u(rng), u(rng));
    const size_t found = tree.Knn(q, max_dist_sq, out);
    const std::vector<float> expected = BruteForce(points, q, k, max_dist_sq);
    ASSERT_EQ(found, expected.size());
    for (size_t j = 0; j < found; ++j) {
      // Equal up to rounding (the summation order may differ); ties are the only freedom.
      EXPECT_FLOAT_EQ(out[j].dist_sq, expected[j]) << "query " << i << " rank " << j;
      const Eigen::Vector3f& p = points[tree.original_index(out[j].slot)];
      EXPECT_EQ(tree.point(out[j].slot), p);
      EXPECT_FLOAT_EQ((p - q).squaredNorm(), out[j].dist_sq);
    }
  }
}

TEST(KdTreeTest, KnnMatchesBruteForce) {
  const auto points = RandomPoints(5000, 1);
  for (size_t k : {1u, 3u, 16u, 100u}) {
    ExpectMatchesBruteForce(points, k, std::numeric_limits<float>::infinity());
  }
}

TEST(KdTreeTest, KnnWithDistanceLimitMatchesBruteForce) {
  const auto points = RandomPoints(5000, 2);
  ExpectMatchesBruteForce(points, 16, 0.03f * 0.03f);
  ExpectMatchesBruteForce(points, 16, 0.0f);
}

TEST(KdTreeTest, DuplicatesAndTinyClouds) {
  std::vector<Eigen::Vector3f> points(100, Eigen::Vector3f(1, 2, 3));
  points.push_back({1, 2, 4});
  ExpectMatchesBruteForce(points, 16, std::numeric_limits<float>::infinity());
  ExpectMatchesBruteForce({Eigen::Vector3f(0, 0, 0)}, 4, std::numeric_limits<float>::infinity());
}

TEST(KdTreeTest, SkipsNonFinitePoints) {
  auto points = RandomPoints(1000, 3);
  points[10].x() = std::numeric_limits<float>::quiet_NaN();
  points[20].z() = std::numeric_limits<float>::infinity();
  const KdTree tree(points);
  ASSERT_EQ(tree.size(), 998u);
  for (uint32_t s = 0; s < tree.size(); ++s) {
    EXPECT_NE(tree.original_index(s), 10u);
    EXPECT_NE(tree.original_index(s), 20u);
  }
  std::vector<Neighbor> out(5);
  EXPECT_EQ(tree.Knn(points[0], std::numeric_limits<float>::infinity(), out), 5u);
}

TEST(KdTreeTest, EmptyTree) {
  const KdTree tree(std::span<const Eigen::Vector3f>{});
  std::vector<Neighbor> out(3);
  EXPECT_EQ(tree.Knn({0, 0, 0}, 1.0f, out), 0u);
  EXPECT_EQ(tree.NearestTwo({0, 0, 0}, 1.0f)[0].slot, KdTree::kNoSlot);
}

TEST(KdTreeTest, NearestTwoMatchesBruteForce) {
  const auto points = RandomPoints(5000, 4);
  const KdTree tree(points);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f);
  for (int i = 0; i < 600; ++i) {
    const Eigen::Vector3f q = i % 3 == 0 ? points[static_cast<size_t>(i) * 5 % points.size()]
                                         : Eigen::Vector3f(u(rng), u(rng), u(rng));
    for (float limit : {std::numeric_limits<float>::infinity(), 0.01f}) {
      float first = std::numeric_limits<float>::infinity(), second = first;
      for (const auto& p : points) {
        const float d = (p - q).squaredNorm();
        if (d < first) {
          second = first;
          first = d;
        } else if (d < second) {
          second = d;
        }
      }
      const auto nb = tree.NearestTwo(q, limit);
      for (int rank = 0; rank < 2; ++rank) {
        const float expected = rank == 0 ? first : second;
        if (expected > limit) {
          EXPECT_EQ(nb[rank].slot, KdTree::kNoSlot) << "query " << i << " rank " << rank;
          continue;
        }
        ASSERT_NE(nb[rank].slot, KdTree::kNoSlot) << "query " << i << " rank " << rank;
        EXPECT_FLOAT_EQ(nb[rank].dist_sq, expected) << "query " << i << " rank " << rank;
        EXPECT_FLOAT_EQ((points[tree.original_index(nb[rank].slot)] - q).squaredNorm(), nb[rank].dist_sq);
      }
    }
  }
}

TEST(KdTreeTest, NearestTwoWithTheExactDistanceAsLimitFindsThosePoints) {
  const auto points = RandomPoints(2000, 5);
  const KdTree tree(points);
  const Eigen::Vector3f q(0.3f, -0.2f, 0.05f);
  const auto free = tree.NearestTwo(q, std::numeric_limits<float>::infinity());
  const auto bounded = tree.NearestTwo(q, free[1].dist_sq);
  EXPECT_EQ(bounded[0].slot, free[0].slot);
  EXPECT_EQ(bounded[1].slot, free[1].slot);
  const auto one = tree.NearestTwo(q, free[1].dist_sq * 0.999f);
  EXPECT_EQ(one[0].slot, free[0].slot);
  EXPECT_EQ(one[1].slot, KdTree::kNoSlot);
}

}  // namespace
}  // namespace vscan::spatial
