#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "fixture_parts.h"
#include "physics/bin_fill.h"
#include "vscan_test/meshes.h"

namespace vscan::physics {
namespace {

BinSpec SettleBin() {
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.20, 0.15, 0.10);
  bin.world_from_bin.translation() = Eigen::Vector3d(0.3, 0.1, 0.05);
  return bin;
}

PartType Block() {
  PartType block;
  block.name = "block";
  block.mesh = vscan::test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02});
  return block;
}

Pose3 InBin(const BinSpec& bin, double x, double y, double z) {
  Pose3 pose = bin.world_from_bin;
  pose.translation() += bin.world_from_bin.linear() * Eigen::Vector3d(x, y, z);
  return pose;
}

TEST(SettlePile, TheBlockOnTopFallsToTheFloorWhenTheOneUnderItIsTaken) {
  const BinSpec bin = SettleBin();
  // Before: a block on the floor with another on it. The lower one is picked; the upper one is left.
  const std::vector<PlacedPart> left{{0, 1, InBin(bin, 0.01, 0, 0.02)}};
  const auto settled = SettlePile(bin, {Block()}, left, FillOptions{});
  ASSERT_TRUE(settled.ok()) << settled.status().ToString();
  EXPECT_EQ(settled->end, FillEnd::kSettled) << settled->message;
  EXPECT_EQ(settled->spawned, 0u);
  ASSERT_EQ(settled->parts.size(), 1u);
  const PlacedPart& part = settled->parts[0];
  EXPECT_EQ(part.instance, 1u);
  const Pose3 bin_from_part = bin.world_from_bin.inverse() * part.world_from_part;
  EXPECT_NEAR(bin_from_part.translation().z(), 0, 0.001);  // its bottom face on the floor
  EXPECT_NEAR(bin_from_part.translation().x(), 0.01, 0.002);
  EXPECT_GT(bin_from_part.linear().col(2).z(), 0.9999);  // still flat
}

TEST(SettlePile, ASettledFillStaysWhereItIs) {
  BinSpec bin = SettleBin();
  const std::vector<PartType> parts{test::AngleBlock(6), test::RoundPin(6)};
  const auto fill = FillBin(bin, parts, FillOptions{});
  ASSERT_TRUE(fill.ok());
  ASSERT_EQ(fill->end, FillEnd::kSettled);
  const auto again = SettlePile(bin, parts, fill->parts, FillOptions{});
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(again->end, FillEnd::kSettled) << again->message;
  ASSERT_EQ(again->parts.size(), fill->parts.size());
  for (size_t i = 0; i < fill->parts.size(); ++i) {
    const PlacedPart& before = fill->parts[i];
    const auto match = std::find_if(again->parts.begin(), again->parts.end(), [&](const PlacedPart& p) {
      return p.type == before.type && p.instance == before.instance;
    });
    ASSERT_NE(match, again->parts.end());
    EXPECT_LT((match->world_from_part.translation() - before.world_from_part.translation()).norm(), 0.003)
        << "part " << i;
  }
}

TEST(SettlePile, BadPlacementsAreRefusedNamingTheField) {
  const BinSpec bin = SettleBin();
  const auto refused = [&](const PlacedPart& part) {
    const auto result = SettlePile(bin, {Block()}, {part}, FillOptions{});
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
    return result.status().message();
  };
  EXPECT_NE(refused({1, 0, Pose3::Identity()}).find("placed[0].type"), std::string::npos);
  Pose3 nan = Pose3::Identity();
  nan.translation().x() = std::nan("");
  EXPECT_NE(refused({0, 0, nan}).find("placed[0].world_from_part"), std::string::npos);
  Pose3 sheared = Pose3::Identity();
  sheared.linear()(0, 1) = 0.5;
  EXPECT_NE(refused({0, 0, sheared}).find("placed[0].world_from_part"), std::string::npos);
}

}  // namespace
}  // namespace vscan::physics
