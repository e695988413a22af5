#include "robot/ik_gradient_descent.h"

#include <random>

#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot/reach.h"
#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

using testing::FixtureChain;

// Sweep caps instead of wall-clock budgets keep these tests deterministic on a loaded machine.
GradientDescentOptions Options(double position_tolerance, double orientation_tolerance, int max_sweeps) {
  GradientDescentOptions options;
  options.position_tolerance = position_tolerance;
  options.orientation_tolerance = orientation_tolerance;
  options.max_sweeps = max_sweeps;
  options.time_budget = std::chrono::microseconds(10'000'000);
  return options;
}

class FixtureGradientDescent : public ::testing::TestWithParam<std::string> {
 protected:
  KinematicChain chain_ = FixtureChain(GetParam());
};

TEST_P(FixtureGradientDescent, PositionGoalsRoundTrip) {
  const GradientDescentOptions options = Options(1e-4, 1e-5, 5000);
  std::mt19937_64 rng(21);
  int solved = 0;
  const int trials = 100;
  for (int t = 0; t < trials; ++t) {
    const Eigen::Vector3d target = ForwardKinematics(chain_, RandomJointPositions(chain_, rng)).value().translation();
    StatusOr<IkResult> result = SolveIkGradientDescent(chain_, PositionGoal(target), chain_.MidLimits(), options);
    if (!result.ok()) continue;
    ++solved;
    EXPECT_LE((ForwardKinematics(chain_, result->joint_positions)->translation() - target).norm(), 1e-4);
  }
  EXPECT_GE(solved, trials * 9 / 10);
}

TEST_P(FixtureGradientDescent, PoseGoalsRoundTripWithLooseTolerance) {
  const GradientDescentOptions options = Options(1e-3, 1e-2, 20000);
  std::mt19937_64 rng(22);
  int solved = 0;
  const int trials = 50;
  for (int t = 0; t < trials; ++t) {
    // Targets near the seed: the paper's method is local.
    Eigen::VectorXd q = chain_.MidLimits() + 0.3 * (RandomJointPositions(chain_, rng) - chain_.MidLimits());
    const Pose3 target = ForwardKinematics(chain_, q).value();
    StatusOr<IkResult> result = SolveIkGradientDescent(chain_, PoseGoal(target), chain_.MidLimits(), options);
    if (!result.ok()) continue;
    ++solved;
    const Pose3 achieved = ForwardKinematics(chain_, result->joint_positions).value();
    EXPECT_LE((achieved.translation() - target.translation()).norm(), 1e-3);
    EXPECT_LE(Eigen::AngleAxisd(achieved.linear().transpose() * target.linear()).angle(), 1e-2);
  }
  EXPECT_GE(solved, trials * 8 / 10);
}

TEST_P(FixtureGradientDescent, LookAtGoals) {
  const GradientDescentOptions options = Options(1e-3, 1e-2, 20000);
  std::mt19937_64 rng(23);
  int solved = 0;
  const int trials = 50;
  for (int t = 0; t < trials; ++t) {
    Eigen::VectorXd q = chain_.MidLimits() + 0.3 * (RandomJointPositions(chain_, rng) - chain_.MidLimits());
    const Pose3 pose = ForwardKinematics(chain_, q).value();
    const Eigen::Vector3d look_at = pose.translation() + 0.5 * pose.linear().col(2);
    StatusOr<IkResult> result =
        SolveIkGradientDescent(chain_, LookAtGoal(pose.translation(), look_at).value(), chain_.MidLimits(), options);
    if (!result.ok()) continue;
    ++solved;
    const Pose3 achieved = ForwardKinematics(chain_, result->joint_positions).value();
    EXPECT_LE((achieved.translation() - pose.translation()).norm(), 1e-3);
    EXPECT_LE(std::acos(std::min(1.0, achieved.linear().col(2).dot(pose.linear().col(2)))), 1e-2);
  }
  EXPECT_GE(solved, trials * 8 / 10);
}

TEST_P(FixtureGradientDescent, FarTargetsFailFast) {
  const double distance = ReachUpperBound(chain_) + 0.5;
  IkResult nearest;
  StatusOr<IkResult> result = SolveIkGradientDescent(
      chain_, PositionGoal(FirstJointOrigin(chain_) + distance * Eigen::Vector3d::UnitY()), chain_.MidLimits(), {},
      &nearest);
  ASSERT_EQ(result.status().code(), StatusCode::kOutOfRange);
  EXPECT_NE(result.status().message().find("misses by 0.5"), std::string::npos) << result.status().message();
}

INSTANTIATE_TEST_SUITE_P(Robots, FixtureGradientDescent, ::testing::Values("ur5", "panda"));

}  // namespace
}  // namespace vscan::robot
