#include "robot/ik_solver.h"

#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot/reach.h"
#include "robot/urdf_chain.h"
#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

using testing::FixtureChain;

class FixtureIk : public ::testing::TestWithParam<std::string> {
 protected:
  FixtureIk() { options_.time_budget = std::chrono::microseconds(100000); }
  KinematicChain chain_ = FixtureChain(GetParam());
  IkOptions options_;  // a generous budget: these tests check answers, ik_bench checks speed
};

// Random reachable poses, seed at mid-limits; checks the solution independently with FK.
TEST_P(FixtureIk, PoseRoundTrips) {
  std::mt19937_64 rng(1234);
  int solved = 0;
  const int trials = 300;
  for (int t = 0; t < trials; ++t) {
    const Pose3 target = ForwardKinematics(chain_, RandomJointPositions(chain_, rng)).value();
    StatusOr<IkResult> result = SolveIk(chain_, PoseGoal(target), chain_.MidLimits(), options_);
    if (!result.ok()) {
      EXPECT_EQ(result.status().code(), StatusCode::kOutOfRange) << result.status().ToString();
      continue;
    }
    ++solved;
    const Pose3 achieved = ForwardKinematics(chain_, result->joint_positions).value();  // also checks limits
    EXPECT_LE((achieved.translation() - target.translation()).norm(), 1e-5);
    EXPECT_LE(Eigen::AngleAxisd(achieved.linear().transpose() * target.linear()).angle(), 1e-5);
    EXPECT_TRUE(achieved.isApprox(result->base_from_tool, 1e-12));
    EXPECT_LE(result->position_error, 1e-5);
    EXPECT_LE(result->orientation_error, 1e-5);
  }
  EXPECT_EQ(solved, trials);
}

TEST_P(FixtureIk, PositionGoals) {
  std::mt19937_64 rng(99);
  for (int t = 0; t < 100; ++t) {
    const Eigen::Vector3d target = ForwardKinematics(chain_, RandomJointPositions(chain_, rng)).value().translation();
    StatusOr<IkResult> result = SolveIk(chain_, PositionGoal(target), chain_.MidLimits(), options_);
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    EXPECT_LE((ForwardKinematics(chain_, result->joint_positions)->translation() - target).norm(), 1e-5);
  }
}

// Stand at a reachable sensor position and look at a point; rotation about the view axis is free.
TEST_P(FixtureIk, LookAtGoals) {
  std::mt19937_64 rng(7);
  int solved = 0;
  const int trials = 100;
  for (int t = 0; t < trials; ++t) {
    const Pose3 pose = ForwardKinematics(chain_, RandomJointPositions(chain_, rng)).value();
    // A point 0.3 m along tool z; the goal carries no roll, so the solver may pick any.
    const Eigen::Vector3d look_at = pose.translation() + 0.3 * pose.linear().col(2);
    const IkGoal goal = LookAtGoal(pose.translation(), look_at).value();
    StatusOr<IkResult> result = SolveIk(chain_, goal, chain_.MidLimits(), options_);
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    ++solved;
    const Pose3 achieved = ForwardKinematics(chain_, result->joint_positions).value();
    EXPECT_LE((achieved.translation() - pose.translation()).norm(), 1e-5);
    const Eigen::Vector3d view = (look_at - achieved.translation()).normalized();
    EXPECT_LE(std::acos(std::min(1.0, view.dot(achieved.linear().col(2)))), 1e-4);
  }
  EXPECT_EQ(solved, trials);
}

TEST_P(FixtureIk, FarTargetsFailFastWithTheMissDistance) {
  const double reach = ReachUpperBound(chain_);
  const Eigen::Vector3d origin = FirstJointOrigin(chain_);
  const Eigen::Vector3d direction = Eigen::Vector3d(1, 2, 0.5).normalized();
  const double distance = reach + 1.7;
  Pose3 target = Pose3::Identity();
  target.translation() = origin + distance * direction;
  IkResult nearest;
  StatusOr<IkResult> result = SolveIk(chain_, PoseGoal(target), chain_.MidLimits(), {}, &nearest);
  ASSERT_EQ(result.status().code(), StatusCode::kOutOfRange);
  double miss = 0;
  EXPECT_FALSE(CheckWithinReach(chain_, target.translation(), "p", &miss).ok());
  EXPECT_NEAR(miss, distance - reach, 1e-9);
  EXPECT_NE(result.status().message().find("misses by 1.7"), std::string::npos) << result.status().message();
  EXPECT_EQ(nearest.joint_positions.size(), chain_.dof());
  EXPECT_EQ(nearest.iterations, 0);  // refused before solving
}

TEST_P(FixtureIk, WithinBoundButUnreachableReportsTheNearestPose) {
  // Inside the crude bound but beyond the true reach: the solver runs out of time.
  const Eigen::Vector3d origin = FirstJointOrigin(chain_);
  const double sampled = SampledReach(chain_, 5000, 1);
  const double distance = 0.5 * (sampled + ReachUpperBound(chain_)) + 0.02;
  IkOptions options;
  options.time_budget = std::chrono::microseconds(2000);
  IkResult nearest;
  StatusOr<IkResult> result =
      SolveIk(chain_, PositionGoal(origin + distance * Eigen::Vector3d::UnitX()), chain_.MidLimits(), options, &nearest);
  ASSERT_EQ(result.status().code(), StatusCode::kOutOfRange) << result.status().ToString();
  EXPECT_NE(result.status().message().find("misses by"), std::string::npos);
  EXPECT_GT(nearest.position_error, 0.01);
  EXPECT_LT(nearest.position_error, distance - 0.5 * sampled);
  EXPECT_TRUE(ForwardKinematics(chain_, nearest.joint_positions).ok());
}

INSTANTIATE_TEST_SUITE_P(Robots, FixtureIk, ::testing::Values("ur5", "panda"));

// Five joints cannot reach arbitrary 6-D poses, but position plus view direction is five
// constraints: solvable only if the roll about the view axis is left free.
TEST(Ik, LookAtOnAFiveJointArm) {
  Pose3 tip_from_tool = Pose3::Identity();
  tip_from_tool.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  tip_from_tool.translation() = Eigen::Vector3d(0, 0, 0.1);
  const KinematicChain chain =
      BuildChain(*testing::FixtureBundle("ur5").model, {"base_link", "wrist_2_link", tip_from_tool}).value();
  ASSERT_EQ(chain.dof(), 5);
  IkOptions options;
  options.time_budget = std::chrono::microseconds(100000);
  std::mt19937_64 rng(8);
  for (int t = 0; t < 50; ++t) {
    const Pose3 pose = ForwardKinematics(chain, RandomJointPositions(chain, rng)).value();
    const Eigen::Vector3d look_at = pose.translation() + 0.4 * pose.linear().col(2);
    StatusOr<IkResult> result =
        SolveIk(chain, LookAtGoal(pose.translation(), look_at).value(), chain.MidLimits(), options);
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    const Pose3 achieved = ForwardKinematics(chain, result->joint_positions).value();
    EXPECT_LE((achieved.translation() - pose.translation()).norm(), 1e-5);
    EXPECT_LE(MeasureGoalErrors(LookAtGoal(pose.translation(), look_at).value(), achieved).orientation, 1e-5);
  }
}

TEST(Ik, RejectsBadInputs) {
  const KinematicChain chain = FixtureChain("ur5");
  Pose3 target = ForwardKinematics(chain, chain.MidLimits()).value();
  EXPECT_EQ(SolveIk(chain, PoseGoal(target), Eigen::VectorXd::Zero(5)).status().code(), StatusCode::kInvalidArgument);
  Pose3 scaled = target;
  scaled.linear() *= 2.0;
  EXPECT_EQ(SolveIk(chain, PoseGoal(scaled), chain.MidLimits()).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(LookAtGoal(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).status().code(), StatusCode::kInvalidArgument);
}

TEST(Ik, SeedAtTheSolutionConvergesImmediately) {
  const KinematicChain chain = FixtureChain("panda");
  const Eigen::VectorXd q = chain.MidLimits();
  StatusOr<IkResult> result = SolveIk(chain, PoseGoal(ForwardKinematics(chain, q).value()), q);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->iterations, 0);
  EXPECT_EQ(result->joint_positions, q);
}

}  // namespace
}  // namespace vscan::robot
