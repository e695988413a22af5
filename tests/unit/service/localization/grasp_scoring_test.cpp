// ScorePoses with a gripper: a grasp planned on each matched estimate of a 40 x 30 x 20 mm block
// tried on the true block, for a suction cup and parallel jaws, and refused or bounded requests.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "service/localization/localization_scoring.h"
#include "service_world.h"
#include "vscan_test/meshes.h"

namespace vscan::service {
namespace {

// Upright, turned 30 degrees about up and away from the origin, so frames must compose right.
Pose3 TrueBlockPose() {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, 0.1, 0.05);
  return pose;
}

// The truth moved by an offset given in the block's own axes.
Pose3 Offset(const Eigen::Vector3d& in_part_axes) {
  Pose3 pose = TrueBlockPose();
  pose.translation() += pose.linear() * in_part_axes;
  return pose;
}

grasping::SuctionCup SmallCup() {
  grasping::SuctionCup cup;
  cup.diameter_m = 0.010;
  cup.stroke_m = 0.010;
  return cup;
}

grasping::ParallelJaws Jaws() {
  grasping::ParallelJaws jaws;
  jaws.min_opening_m = 0.002;
  jaws.max_opening_m = 0.035;  // across the 30 mm side, never the 40 mm one
  return jaws;
}

class GraspScoringTest : public ::testing::Test {
 protected:
  ScoringPlan Plan(const grasping::Gripper& gripper, const std::vector<Pose3>& estimates) {
    ScoringPlan plan;
    plan.parts.push_back({block_, 1, std::nullopt});
    plan.options.keep_top_estimates = false;
    // Matched however far off (up to a diameter): every estimate gets its grasp judged.
    plan.options.add_threshold = 1.0;
    // One true block per estimate, far apart (1 m), so that each estimate matches its own.
    for (size_t i = 0; i < estimates.size(); ++i) {
      Pose3 apart = Pose3::Identity();
      apart.translation() = Eigen::Vector3d(double(i), 0, 0);
      plan.truth.push_back({0, apart * TrueBlockPose(), 1.0});
      plan.estimates.push_back({0, apart * estimates[i], 1.0});
    }
    plan.grasp = GraspScoring{gripper, {}, Eigen::Vector3d::UnitZ()};
    return plan;
  }

  // The verdict of each true block's match, in order.
  std::vector<GraspVerdict> Verdicts(const ScoringPlan& plan) {
    const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
    EXPECT_TRUE(scores.ok()) << scores.status().ToString();
    std::vector<GraspVerdict> out;
    if (!scores.ok()) return out;
    EXPECT_TRUE(scores->grasp.has_value());
    const localization::PartScore& part = scores->scan.parts[0];
    const PartGraspScore& grasps = scores->grasp->parts[0];
    out.resize(plan.truth.size());
    for (size_t i = 0; i < part.instances.size(); ++i) {
      EXPECT_EQ(part.instances[i].estimate_index, part.instances[i].true_index);
      EXPECT_TRUE(grasps.instances[i].has_value());
      out[part.instances[i].true_index] = *grasps.instances[i];
    }
    return out;
  }

  testing::ServiceWorld world_;
  std::string block_ = world_.AddMesh(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02}), "block");
};

TEST_F(GraspScoringTest, TheCupPlannedOnTheTopHoldsWhereTheTrueTopMeetsIt) {
  // The grasp the estimates plan with: the best one from above, on the top face.
  const auto grasps = grasping::GenerateGrasps(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02}), SmallCup(), {});
  ASSERT_TRUE(grasps.ok());
  const auto from_above = std::find_if(grasps->begin(), grasps->end(), [](const grasping::Grasp& g) {
    return g.approach.dot(-Eigen::Vector3d::UnitZ()) >= 0.5;
  });
  ASSERT_NE(from_above, grasps->end());
  const Eigen::Vector3d contact = from_above->part_from_tool.translation();
  EXPECT_NEAR(contact.z(), 0.02, 1e-6);
  ASSERT_LT(std::abs(contact.x()), 0.015);
  // 17 mm sideways towards the nearer end puts the planned contact past the true top's edge.
  const double towards_end = contact.x() >= 0 ? 0.017 : -0.017;

  Pose3 quarter_turn = TrueBlockPose();
  quarter_turn.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()) * quarter_turn.linear();
  const ScoringPlan plan = Plan(SmallCup(), {TrueBlockPose(), Offset({0, 0, 0.005}), Offset({0, 0, -0.003}),
                                             Offset({towards_end, 0, 0}), quarter_turn});
  const std::vector<GraspVerdict> verdicts = Verdicts(plan);
  ASSERT_EQ(verdicts.size(), 5u);
  EXPECT_TRUE(verdicts[0].holds) << verdicts[0].failure;
  EXPECT_TRUE(verdicts[0].failure.empty());
  // 5 mm too high: the cup stops short, beyond the 2 mm overtravel.
  EXPECT_FALSE(verdicts[1].holds);
  EXPECT_EQ(verdicts[1].failure, "the cup meets no surface of the part");
  // 3 mm too low: the bellows take the early surface up.
  EXPECT_TRUE(verdicts[2].holds) << verdicts[2].failure;
  EXPECT_FALSE(verdicts[3].holds);
  EXPECT_FALSE(verdicts[3].failure.empty());
  // A quarter turn about up keeps the planned contact on the true top (within 15 mm of the middle).
  EXPECT_TRUE(verdicts[4].holds) << verdicts[4].failure;

  const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  ASSERT_TRUE(scores.ok());
  EXPECT_EQ(scores->grasp->holds, 3u);
  EXPECT_EQ(scores->grasp->valid_instances, 5u);
  EXPECT_DOUBLE_EQ(*scores->grasp->success, 3.0 / 5.0);
  EXPECT_DOUBLE_EQ(*scores->grasp->parts[0].success, 3.0 / 5.0);
}

TEST_F(GraspScoringTest, AtBopsThresholdAFarEstimateIsUnmatchedAndItsGraspNotTried) {
  // 5 mm high is within 10% of the block's 53.9 mm diameter and matched (its grasp fails); 17 mm
  // sideways is not matched, so it has no verdict and counts as a failed grasp.
  ScoringPlan plan = Plan(SmallCup(), {TrueBlockPose(), Offset({0, 0, 0.005}), Offset({0.017, 0, 0})});
  plan.options.add_threshold = 0.1;
  const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  ASSERT_TRUE(scores.ok()) << scores.status().ToString();
  EXPECT_EQ(scores->scan.parts[0].add_correct, 2u);
  EXPECT_EQ(scores->grasp->holds, 1u);
  EXPECT_DOUBLE_EQ(*scores->grasp->success, 1.0 / 3.0);
  size_t verdicts = 0;
  for (const auto& verdict : scores->grasp->parts[0].instances) verdicts += verdict.has_value();
  EXPECT_EQ(verdicts, 2u);
}

TEST_F(GraspScoringTest, AnUnmatchedTrueInstanceCountsAsAFailedGrasp) {
  ScoringPlan plan = Plan(SmallCup(), {TrueBlockPose()});
  Pose3 second = TrueBlockPose();
  second.translation().y() += 0.5;
  plan.truth.push_back({0, second, 1.0});
  const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  ASSERT_TRUE(scores.ok()) << scores.status().ToString();
  EXPECT_EQ(scores->grasp->holds, 1u);
  EXPECT_DOUBLE_EQ(*scores->grasp->success, 0.5);
  EXPECT_DOUBLE_EQ(*scores->scan.add_recall, 0.5);
  EXPECT_FALSE(scores->grasp->parts[0].instances[1].has_value());
}

TEST_F(GraspScoringTest, AnEstimateWithoutAGraspFromAboveFailsSayingSo) {
  // One grasp only, and up along its approach: the grasp points up, not down.
  grasping::GraspOptions one;
  one.max_grasps = 1;
  const auto grasps = grasping::GenerateGrasps(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02}), SmallCup(), one);
  ASSERT_TRUE(grasps.ok());
  ASSERT_EQ(grasps->size(), 1u);
  ScoringPlan plan = Plan(SmallCup(), {TrueBlockPose()});
  plan.grasp->grasp_options = one;
  plan.grasp->up = TrueBlockPose().linear() * grasps->front().approach;
  std::vector<GraspVerdict> verdicts = Verdicts(plan);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_FALSE(verdicts[0].holds);
  EXPECT_EQ(verdicts[0].failure, kNoGraspFromAbove);
  // Up opposite: the same grasp comes straight down and holds.
  plan.grasp->up = -plan.grasp->up;
  verdicts = Verdicts(plan);
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_TRUE(verdicts[0].holds) << verdicts[0].failure;
}

TEST_F(GraspScoringTest, ACupWiderThanEveryFaceHasNoGraspOnThePart) {
  grasping::SuctionCup wide;
  wide.diameter_m = 0.05;  // wider than the block's 40 mm length
  const std::vector<GraspVerdict> verdicts = Verdicts(Plan(wide, {TrueBlockPose()}));
  ASSERT_EQ(verdicts.size(), 1u);
  EXPECT_FALSE(verdicts[0].holds);
  EXPECT_EQ(verdicts[0].failure, kNoGraspOfThePart);
}

TEST_F(GraspScoringTest, JawsAcrossTheThirtyMillimetreSideFailWithAFourMillimetreErrorAlongTheirClosingAxis) {
  const std::vector<GraspVerdict> verdicts = Verdicts(Plan(Jaws(), {TrueBlockPose(), Offset({0, 0.004, 0})}));
  ASSERT_EQ(verdicts.size(), 2u);
  EXPECT_TRUE(verdicts[0].holds) << verdicts[0].failure;
  // The open jaw reaches 17.5 mm each side of the planned centre; the true side face lies 19 mm off.
  EXPECT_FALSE(verdicts[1].holds);
  EXPECT_EQ(verdicts[1].failure, "a finger lands on the part");
}

TEST_F(GraspScoringTest, WithoutAGripperThereAreNoGraspFigures) {
  ScoringPlan plan = Plan(SmallCup(), {TrueBlockPose()});
  plan.grasp.reset();
  const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  ASSERT_TRUE(scores.ok());
  EXPECT_FALSE(scores->grasp.has_value());
  EXPECT_EQ(scores->scan.parts[0].add_correct, 1u);
}

TEST_F(GraspScoringTest, ANonFiniteGripperOrUpIsRefusedNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  grasping::SuctionCup cup = SmallCup();
  cup.stroke_m = nan;
  ScoringPlan plan = Plan(cup, {TrueBlockPose()});
  auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  EXPECT_EQ(scores.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(scores.status().field(), "gripper.suction.stroke_m");

  grasping::ParallelJaws jaws = Jaws();
  jaws.finger_width_m = std::numeric_limits<double>::infinity();
  plan = Plan(jaws, {TrueBlockPose()});
  scores = ScorePosesWithGrasps(world_.context().registry, plan);
  EXPECT_EQ(scores.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(scores.status().field(), "gripper.jaws.finger_width_m");

  for (const Eigen::Vector3d& up :
       std::vector<Eigen::Vector3d>{Eigen::Vector3d::Zero(), Eigen::Vector3d(nan, 0, 1), Eigen::Vector3d(0, 0, 1e-300)}) {
    plan = Plan(SmallCup(), {TrueBlockPose()});
    plan.grasp->up = up;
    scores = ScorePosesWithGrasps(world_.context().registry, plan);
    EXPECT_EQ(scores.status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(scores.status().field(), "up");
  }
  // Huge but finite is a direction.
  plan = Plan(SmallCup(), {TrueBlockPose()});
  plan.grasp->up = Eigen::Vector3d(0, 1e300, 1e300);
  EXPECT_TRUE(ScorePosesWithGrasps(world_.context().registry, plan).ok());
  plan = Plan(SmallCup(), {TrueBlockPose()});
  plan.grasp->grasp_options.candidates = 0;
  scores = ScorePosesWithGrasps(world_.context().registry, plan);
  EXPECT_EQ(scores.status().field(), "grasp_options.candidates");
}

TEST_F(GraspScoringTest, GraspGenerationOfManyPartTypesCountsInTheScoringBound) {
  // Each part type's generation alone is within GenerateGrasps' own 2e9 (50000 candidates x
  // (12 triangles + 2 x 2000 samples x 8 approaches) = 1.6e9); two exceed the 3e9 of one call.
  grasping::GraspOptions heavy;
  heavy.candidates = 50000;
  heavy.surface_samples = 2000;
  ScoringPlan plan = Plan(Jaws(), {TrueBlockPose()});
  plan.grasp->grasp_options = heavy;
  const std::string second = world_.AddMesh(test::MakeBox({-0.02, -0.02, 0}, {0.02, 0.02, 0.02}), "square block");
  plan.parts.push_back({second, 1, std::nullopt});
  plan.truth.push_back({1, TrueBlockPose(), 1.0});
  plan.estimates.push_back({1, TrueBlockPose(), 1.0});
  const auto start = std::chrono::steady_clock::now();
  const auto scores = ScorePosesWithGrasps(world_.context().registry, plan);
  EXPECT_EQ(scores.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(scores.status().field(), "estimates");
  // Refused before any grasp is generated.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  // Without a gripper the same poses are cheap.
  plan.grasp.reset();
  EXPECT_TRUE(ScorePosesWithGrasps(world_.context().registry, plan).ok());
}

TEST_F(GraspScoringTest, ACancelledCallStops) {
  std::atomic<bool> cancel{true};
  const auto scores = ScorePosesWithGrasps(world_.context().registry, Plan(SmallCup(), {TrueBlockPose()}), &cancel);
  EXPECT_EQ(scores.status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::service
