#include "robot/encoder_noise.h"

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

TEST(EncoderNoise, SameSeedSameBits) {
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(7, -1.0, 1.0);
  const Eigen::VectorXd sigma = Eigen::VectorXd::Constant(7, 1e-3);
  const Eigen::VectorXd a = AddEncoderNoise(q, sigma, 77).value();
  const Eigen::VectorXd b = AddEncoderNoise(q, sigma, 77).value();
  EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * 7), 0);
  EXPECT_NE(a, AddEncoderNoise(q, sigma, 78).value());
  EXPECT_NE(a, q);
}

TEST(EncoderNoise, SampleSigmaMatchesPerJoint) {
  const Eigen::VectorXd q = Eigen::Vector3d(0.5, -0.2, 0.1);
  const Eigen::VectorXd sigma = Eigen::Vector3d(1e-3, 2e-2, 0.0);
  const int draws = 20000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
  for (int s = 0; s < draws; ++s) {
    const Eigen::Vector3d d = AddEncoderNoise(q, sigma, 1000 + s).value() - q;
    sum += d;
    sum_sq += d.cwiseProduct(d);
  }
  for (int i = 0; i < 2; ++i) {
    const double mean = sum[i] / draws;
    const double sd = std::sqrt(sum_sq[i] / draws - mean * mean);
    EXPECT_NEAR(sd / sigma[i], 1.0, 0.03) << "joint " << i;
    EXPECT_NEAR(mean, 0.0, 4 * sigma[i] / std::sqrt(draws)) << "joint " << i;
  }
  EXPECT_EQ(sum_sq[2], 0.0);
}

TEST(EncoderNoise, AchievedPoseDiffersFromCommanded) {
  const KinematicChain chain = testing::FixtureChain("ur5");
  const Eigen::VectorXd q = chain.MidLimits();
  const Eigen::VectorXd noisy = AddEncoderNoise(q, Eigen::VectorXd::Constant(6, 1e-3), 5).value();
  const double moved = (ForwardKinematics(chain, noisy)->translation() - ForwardKinematics(chain, q)->translation()).norm();
  EXPECT_GT(moved, 1e-5);
  EXPECT_LT(moved, 1e-2);
}

TEST(EncoderNoise, RejectsBadSigma) {
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
  EXPECT_EQ(AddEncoderNoise(q, Eigen::VectorXd::Zero(2), 1).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(AddEncoderNoise(q, Eigen::Vector3d(0, -1, 0), 1).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(AddEncoderNoise(q, Eigen::Vector3d(0, NAN, 0), 1).status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vscan::robot
