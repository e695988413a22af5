#include "picking/empty_bin.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>

#include "vscan_test/meshes.h"

namespace vscan::picking {
namespace {

physics::PartType Block(size_t count) {
  physics::PartType block;
  block.name = "block";
  block.mesh = test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02});
  block.count = count;
  return block;
}

// Six blocks dropped into a small box bin; a 10 mm cup; no arm (every clear grasp is reachable).
class EmptyBinTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cell_.bin.inner_size = Eigen::Vector3d(0.16, 0.12, 0.10);
    cell_.types = {Block(6)};
    grasping::SuctionCup cup;
    cup.diameter_m = 0.010;
    cell_.gripper = cup;
    grasping::GraspOptions options;
    options.max_grasps = 1000;
    auto grasps = grasping::GenerateGrasps(cell_.types[0].mesh, cell_.gripper, options);
    ASSERT_TRUE(grasps.ok());
    cell_.grasps = {*grasps};
    auto fill = physics::FillBin(cell_.bin, cell_.types, cell_.physics);
    ASSERT_TRUE(fill.ok());
    ASSERT_EQ(fill->end, physics::FillEnd::kSettled);
    pile_ = fill->parts;
    ASSERT_EQ(pile_.size(), 6u);
  }

  // The localizer as a perfect one, or off by `offset` (world frame); the highest part surest.
  Perceive Seeing(const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) const {
    return [offset](const std::vector<physics::PlacedPart>& pile) -> StatusOr<std::vector<Estimate>> {
      std::vector<Estimate> out;
      for (const physics::PlacedPart& part : pile) {
        Pose3 pose = part.world_from_part;
        pose.translation() += offset;
        out.push_back({part.type, pose, part.world_from_part.translation().z()});
      }
      return out;
    };
  }

  Cell cell_;
  std::vector<physics::PlacedPart> pile_;
};

TEST_F(EmptyBinTest, ACellThatSeesThePartsWhereTheyLieEmptiesTheBin) {
  std::vector<size_t> seen;
  const auto result = EmptyBin(cell_, pile_, Seeing(), {}, nullptr,
                               [&](const PickStep&, const std::vector<physics::PlacedPart>& after) {
                                 seen.push_back(after.size());
                               });
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->end, "empty");
  EXPECT_EQ(result->picked + result->fell_out, 6u);
  EXPECT_TRUE(result->pile.empty());
  std::set<size_t> instances;
  for (const PickStep& step : result->steps) {
    EXPECT_EQ(step.outcome, StepOutcome::kPicked) << step.detail;
    ASSERT_TRUE(step.picked.has_value());
    instances.insert(step.picked->instance);
    // The cup comes from above.
    EXPECT_LT(step.world_from_tool.linear().col(2).z(), -0.5);
  }
  EXPECT_EQ(instances.size(), result->picked);  // every part taken once
  ASSERT_EQ(seen.size(), result->steps.size());
  for (size_t i = 1; i < seen.size(); ++i) EXPECT_LT(seen[i], seen[i - 1]);
}

TEST_F(EmptyBinTest, EstimatesTooHighLeaveTheCupShortAndTheCellGivesUp) {
  // 15 mm too high: the cup stops 15 mm above the true face (2 mm overtravel).
  const auto result = EmptyBin(cell_, pile_, Seeing(Eigen::Vector3d(0, 0, 0.015)), {});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->end, "failures in a row");
  EXPECT_EQ(result->picked, 0u);
  ASSERT_EQ(result->steps.size(), 3u);
  for (const PickStep& step : result->steps) EXPECT_EQ(step.outcome, StepOutcome::kWrongPose) << step.detail;
  // Each retry planned another tool pose.
  EXPECT_GT((result->steps[0].world_from_tool.translation() - result->steps[1].world_from_tool.translation()).norm(),
            0.005);
  EXPECT_EQ(result->pile.size(), 6u);
}

TEST_F(EmptyBinTest, NothingFoundEndsTheRunAndACancelStopsIt) {
  const Perceive blind = [](const std::vector<physics::PlacedPart>&) -> StatusOr<std::vector<Estimate>> {
    return std::vector<Estimate>{};
  };
  auto result = EmptyBin(cell_, pile_, blind, {});
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->end, "nothing found");
  ASSERT_EQ(result->steps.size(), 1u);
  EXPECT_EQ(result->steps[0].outcome, StepOutcome::kNothingFound);
  std::atomic<bool> cancel{true};
  result = EmptyBin(cell_, pile_, Seeing(), {}, &cancel);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->end, "cancelled");
  EXPECT_TRUE(result->steps.empty());
}

TEST_F(EmptyBinTest, BadCellsAndEstimatesAreRefusedNamingTheField) {
  Cell bad = cell_;
  bad.grasps.clear();
  EXPECT_NE(EmptyBin(bad, pile_, Seeing(), {}).status().message().find("cell.grasps"), std::string::npos);
  auto pile = pile_;
  pile[0].type = 3;
  EXPECT_NE(EmptyBin(cell_, pile, Seeing(), {}).status().message().find("pile[0].type"), std::string::npos);
  const Perceive wrong_type = [](const std::vector<physics::PlacedPart>&) -> StatusOr<std::vector<Estimate>> {
    return std::vector<Estimate>{{7, Pose3::Identity(), 1}};
  };
  EXPECT_NE(EmptyBin(cell_, pile_, wrong_type, {}).status().message().find("estimates[0].type"), std::string::npos);
}

}  // namespace
}  // namespace vscan::picking
