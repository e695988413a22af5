#include "registration/normal_equations.h"

#include <random>

#include <gtest/gtest.h>

#include "icp_test_util.h"

namespace vscan::registration {
namespace {

TEST(NormalEquationsTest, SolvesAnExactlyLinearProblem) {
  // Residuals that are exactly linear in the increment: r = -J.x for a known x.
  Vector6d x;
  x << 0.01, -0.02, 0.005, 0.003, 0.001, -0.002;
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0.0, 1.0);
  NormalEquations a, b;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(g(rng), g(rng), g(rng));
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    Vector6d j;
    j << p.cross(n), n;
    (i % 2 == 0 ? a : b).Add(p, n, -j.dot(x), 1.0 + 0.1 * (i % 3));
  }
  a.Merge(b);
  const auto solved = a.Solve();
  ASSERT_TRUE(solved.has_value());
  EXPECT_LT((*solved - x).norm(), 1e-12);
}

TEST(NormalEquationsTest, UnconstrainedDirectionsAreReported) {
  NormalEquations planar;
  for (int i = 0; i < 50; ++i) planar.Add(Eigen::Vector3d(i * 0.01, -i * 0.02, 0.0), Eigen::Vector3d::UnitZ(), 0.001, 1.0);
  EXPECT_FALSE(planar.Solve().has_value());
  EXPECT_FALSE(NormalEquations{}.Solve().has_value());
}

TEST(NormalEquationsTest, IncrementRotatesAboutTheCentre) {
  Vector6d x;
  x << 0.0, 0.0, 0.1, 0.0, 0.0, 0.0;
  const Eigen::Vector3d centre(1.0, 2.0, 3.0);
  Pose3 pose = IncrementPose(x, centre);
  EXPECT_LT((pose * centre - centre).norm(), 1e-15);
  EXPECT_NEAR(testing::RotationErrorDeg(pose, Pose3::Identity()), 0.1 / testing::kDeg, 1e-12);
  EXPECT_LT((pose.linear().transpose() * pose.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-15);
  pose.linear() *= 1.001;
  Reorthonormalise(pose);
  EXPECT_LT((pose.linear().transpose() * pose.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

}  // namespace
}  // namespace vscan::registration
