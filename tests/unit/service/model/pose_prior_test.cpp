// The firmness of a commanded sensor pose against the spread of the poses the arm really reaches
// under its encoder noise, sampled.

#include "service/model/pose_prior.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "model_test_world.h"
#include "robot/encoder_noise.h"
#include "robot_registry/arm_kinematics.h"

namespace vscan::service {
namespace {

using testing::ModelWorld;

Eigen::Matrix<double, 6, 1> Perturbation(const Pose3& from, const Pose3& to) {
  const Pose3 e = from.inverse() * to;
  const Eigen::AngleAxisd turn(e.linear());
  Eigen::Matrix<double, 6, 1> v;
  v << turn.angle() * turn.axis(), e.translation();
  return v;
}

TEST(PosePriorTest, TheCovarianceIsThatOfThePosesTheNoisyArmReaches) {
  constexpr double kSigma = 0.001;
  ModelWorld world(kSigma);
  const auto mounted = world.world.context().robots.Mount(world.mount_id);
  ASSERT_TRUE(mounted.ok()) << mounted.status().ToString();
  const Eigen::VectorXd q = mounted->chain->MidLimits() + Eigen::VectorXd::Constant(mounted->chain->dof(), 0.3);
  const auto information = CommandedPoseInformation(*mounted, q, /*encoder_noise=*/true);
  ASSERT_TRUE(information.ok()) << information.status().ToString();
  const PoseInformation predicted = information->inverse();

  const auto commanded = robot_registry::CommandJoints(*mounted->chain, mounted->placement, q, "q");
  ASSERT_TRUE(commanded.ok());
  constexpr int kDraws = 4000;
  PoseInformation sampled = PoseInformation::Zero();
  for (int i = 0; i < kDraws; ++i) {
    const auto noisy = robot::AddEncoderNoise(q, mounted->placement.encoder_sigma, 1000 + i);
    ASSERT_TRUE(noisy.ok());
    const auto reached = robot_registry::CommandJoints(*mounted->chain, mounted->placement, *noisy, "q");
    ASSERT_TRUE(reached.ok());
    const Eigen::Matrix<double, 6, 1> v = Perturbation(commanded->commanded_pose, reached->commanded_pose);
    sampled += v * v.transpose() / kDraws;
  }
  // Each standard deviation within 10% of the sampled one (4000 draws: about 2% sampling error).
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(std::sqrt(predicted(k, k)), std::sqrt(sampled(k, k)), 0.1 * std::sqrt(sampled(k, k))) << k;
  }
  // And the arm's noise is what it should be: about a milliradian turns the sensor by about as much.
  EXPECT_GT(std::sqrt(predicted(0, 0) + predicted(1, 1) + predicted(2, 2)), kSigma);
}

TEST(PosePriorTest, AnArmWithoutEncoderNoiseKnowsItsPoseToAMicrometre) {
  ModelWorld world(0.001);
  const auto mounted = world.world.context().robots.Mount(world.mount_id);
  ASSERT_TRUE(mounted.ok());
  const auto information = CommandedPoseInformation(*mounted, mounted->chain->MidLimits(), /*encoder_noise=*/false);
  ASSERT_TRUE(information.ok());
  EXPECT_TRUE(information->isApprox(PoseInformation::Identity() * 1e12));
}

TEST(PosePriorTest, JointsThatDoNotFitTheChainAreRefused) {
  ModelWorld world(0.001);
  const auto mounted = world.world.context().robots.Mount(world.mount_id);
  ASSERT_TRUE(mounted.ok());
  EXPECT_FALSE(CommandedPoseInformation(*mounted, Eigen::VectorXd::Zero(2), true).ok());
}

}  // namespace
}  // namespace vscan::service
