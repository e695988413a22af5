#include "physics/bin_fill.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "fixture_parts.h"
#include "tote_mesh.h"

namespace vscan::physics {
namespace {

// A small bin, moved and turned in the world so that the bin frame matters.
BinSpec SmallFillBin() {
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.20, 0.15, 0.10);
  bin.wall_thickness = 0.01;
  bin.world_from_bin = RotationAboutLine(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.4);
  bin.world_from_bin.translation() = Eigen::Vector3d(0.5, -0.2, 0.1);
  return bin;
}

std::vector<PartType> Mix(size_t blocks, size_t pins) { return {test::AngleBlock(blocks), test::RoundPin(pins)}; }

FillResult Fill(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options) {
  auto result = FillBin(bin, parts, options);
  EXPECT_TRUE(result.ok()) << result.status().ToString();
  return result.ok() ? *result : FillResult{};
}

TEST(FillBin, SettledPartsLieInsideTheBinBelowTheRim) {
  const BinSpec bin = SmallFillBin();
  const auto parts = Mix(6, 6);
  const FillResult result = Fill(bin, parts, FillOptions{});
  EXPECT_EQ(result.end, FillEnd::kSettled) << result.message;
  EXPECT_EQ(result.spawned, 12u);
  EXPECT_EQ(result.parts.size(), 12u);
  EXPECT_TRUE(result.outside.empty());
  constexpr double kTolerance = 0.002;
  const Pose3 bin_from_world = bin.world_from_bin.inverse();
  for (const PlacedPart& placed : result.parts) {
    for (const Eigen::Vector3f& v : parts[placed.type].mesh.vertices) {
      const Eigen::Vector3d p = bin_from_world * placed.world_from_part * v.cast<double>();
      EXPECT_LE(std::abs(p.x()), 0.5 * bin.inner_size.x() + kTolerance);
      EXPECT_LE(std::abs(p.y()), 0.5 * bin.inner_size.y() + kTolerance);
      EXPECT_GE(p.z(), -kTolerance);
      EXPECT_LE(p.z(), bin.inner_size.z() + kTolerance);
    }
  }
}

TEST(FillBin, PartsBarelyInterpenetrate) {
  const FillResult result = Fill(SmallFillBin(), Mix(8, 8), FillOptions{});
  EXPECT_EQ(result.end, FillEnd::kSettled) << result.message;
  EXPECT_LT(result.max_part_part_penetration_m, 0.002);
  EXPECT_LT(result.max_part_bin_penetration_m, 0.002);
}

TEST(FillBin, OneSeedGivesTheSameBitsAnotherSeedOtherPoses) {
  FillOptions options;
  options.seed = 7;
  const auto parts = Mix(4, 4);
  const FillResult first = Fill(SmallFillBin(), parts, options);
  const FillResult again = Fill(SmallFillBin(), parts, options);
  options.seed = 8;
  const FillResult other = Fill(SmallFillBin(), parts, options);
  ASSERT_EQ(first.parts.size(), again.parts.size());
  EXPECT_EQ(first.steps, again.steps);
  bool all_equal_to_other = first.parts.size() == other.parts.size();
  for (size_t i = 0; i < first.parts.size(); ++i) {
    EXPECT_EQ(first.parts[i].type, again.parts[i].type);
    EXPECT_EQ(first.parts[i].instance, again.parts[i].instance);
    EXPECT_TRUE(first.parts[i].world_from_part.matrix() == again.parts[i].world_from_part.matrix()) << i;
    if (all_equal_to_other) {
      all_equal_to_other = first.parts[i].world_from_part.matrix() == other.parts[i].world_from_part.matrix();
    }
  }
  EXPECT_FALSE(all_equal_to_other);
}

TEST(FillBin, MorePartsThanTheBinHoldsEndsFull) {
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.08, 0.08, 0.04);
  const FillResult result = Fill(bin, {test::AngleBlock(40)}, FillOptions{});
  EXPECT_EQ(result.end, FillEnd::kFull) << result.message;
  EXPECT_LT(result.spawned, 40u);
  EXPECT_LT(result.parts.size(), 40u);
  EXPECT_GT(result.parts.size(), 0u);
}

TEST(FillBin, ATinyTimeBoundEndsAtTheBound) {
  FillOptions options;
  options.max_simulated_s = 0.05;
  const FillResult result = Fill(SmallFillBin(), Mix(4, 4), options);
  EXPECT_EQ(result.end, FillEnd::kTimeBound) << result.message;
  EXPECT_EQ(result.steps, 12u);  // ceil(0.05 * 240)
  EXPECT_NEAR(result.simulated_s, 0.05, 1e-3);
}

TEST(FillBin, CancelStopsTheRun) {
  std::atomic<bool> cancel{true};
  auto result = FillBin(SmallFillBin(), Mix(4, 4), FillOptions{}, &cancel);
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->end, FillEnd::kCancelled);
  EXPECT_EQ(result->steps, 0u);
}

std::string FieldOf(const BinSpec& bin, const std::vector<PartType>& parts, const FillOptions& options) {
  auto result = FillBin(bin, parts, options);
  EXPECT_FALSE(result.ok());
  if (result.ok()) return "";
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  return result.status().field();
}

TEST(FillBin, BadInputNamesItsField) {
  const BinSpec good_bin = SmallFillBin();
  const auto good_parts = Mix(2, 2);
  const FillOptions good_options;

  BinSpec bin = good_bin;
  bin.inner_size.y() = -0.1;
  EXPECT_EQ(FieldOf(bin, good_parts, good_options), "bin.inner_size");
  bin = good_bin;
  bin.wall_thickness = std::nan("");
  EXPECT_EQ(FieldOf(bin, good_parts, good_options), "bin.wall_thickness");

  auto parts = good_parts;
  parts[1].mesh = TriangleMesh{};
  EXPECT_EQ(FieldOf(good_bin, parts, good_options), "parts[1].mesh");
  parts = good_parts;
  parts[1].count = 501;
  EXPECT_EQ(FieldOf(good_bin, parts, good_options), "parts[1].count");
  parts = good_parts;
  parts[0].count = 300;
  parts[1].count = 300;
  EXPECT_EQ(FieldOf(good_bin, parts, good_options), "parts[1].count");
  parts = good_parts;
  parts[0].mass_kg = 0.0;
  EXPECT_EQ(FieldOf(good_bin, parts, good_options), "parts[0].mass_kg");
  EXPECT_EQ(FieldOf(good_bin, {}, good_options), "parts");

  FillOptions options = good_options;
  options.time_step_s = 0.1;
  EXPECT_EQ(FieldOf(good_bin, good_parts, options), "options.time_step_s");
  options = good_options;
  options.time_step_s = 5e-5;
  EXPECT_EQ(FieldOf(good_bin, good_parts, options), "options.time_step_s");
  options = good_options;
  options.max_simulated_s = -1;
  EXPECT_EQ(FieldOf(good_bin, good_parts, options), "options.max_simulated_s");
  options = good_options;
  options.settle_steps = 0;
  EXPECT_EQ(FieldOf(good_bin, good_parts, options), "options.settle_steps");
}

// A tote with sloped walls (16 x 12 cm floor, 22 x 16 cm opening, 10 cm deep), moved and turned.
constexpr float kFloorX = 0.16f, kFloorY = 0.12f, kTopX = 0.22f, kTopY = 0.16f, kDepth = 0.10f;

BinSpec ToteBin() {
  BinSpec bin = SmallFillBin();
  bin.mesh = test::SlopedTote(kFloorX, kFloorY, kTopX, kTopY, kDepth);
  return bin;
}

TEST(FillBin, PartsDroppedIntoAMeshBinSettleWithinItsSlopedWalls) {
  const BinSpec bin = ToteBin();
  const auto parts = Mix(6, 4);
  const FillResult result = Fill(bin, parts, FillOptions{});
  EXPECT_EQ(result.end, FillEnd::kSettled) << result.message;
  EXPECT_EQ(result.parts.size(), 10u);
  EXPECT_TRUE(result.outside.empty());
  EXPECT_LT(result.max_part_bin_penetration_m, 0.002);
  constexpr double kTolerance = 0.002;
  const Pose3 bin_from_world = bin.world_from_bin.inverse();
  double lowest = 1.0;
  for (const PlacedPart& placed : result.parts) {
    for (const Eigen::Vector3f& v : parts[placed.type].mesh.vertices) {
      const Eigen::Vector3d p = bin_from_world * placed.world_from_part * v.cast<double>();
      lowest = std::min(lowest, p.z());
      // Inside the frustum the walls span (so inside the mesh's bounding box too), not below the floor.
      const double t = std::clamp(p.z() / kDepth, 0.0, 1.0);
      EXPECT_LE(std::abs(p.x()), 0.5 * (kFloorX + t * (kTopX - kFloorX)) + kTolerance);
      EXPECT_LE(std::abs(p.y()), 0.5 * (kFloorY + t * (kTopY - kFloorY)) + kTolerance);
      EXPECT_GE(p.z(), -kTolerance);
      EXPECT_LE(p.z(), kDepth + kTolerance);
    }
  }
  EXPECT_LT(lowest, 0.002);  // the lowest part lies on the floor
}

TEST(FillBin, AMeshBinFillsTheSameBitsForOneSeed) {
  FillOptions options;
  options.seed = 11;
  const auto parts = Mix(3, 3);
  const FillResult first = Fill(ToteBin(), parts, options);
  const FillResult again = Fill(ToteBin(), parts, options);
  EXPECT_EQ(first.end, FillEnd::kSettled) << first.message;
  ASSERT_EQ(first.parts.size(), again.parts.size());
  EXPECT_EQ(first.steps, again.steps);
  for (size_t i = 0; i < first.parts.size(); ++i) {
    EXPECT_TRUE(first.parts[i].world_from_part.matrix() == again.parts[i].world_from_part.matrix()) << i;
  }
}

TEST(FillBin, AMeshBinWhoseOpeningIsNarrowerThanThePartsEndsFull) {
  BinSpec bin;
  bin.mesh = test::SlopedTote(0.01f, 0.01f, 0.02f, 0.02f, 0.02f);  // blocks are about 3.4 cm
  const FillResult result = Fill(bin, {test::AngleBlock(3)}, FillOptions{});
  EXPECT_EQ(result.end, FillEnd::kFull) << result.message;
  EXPECT_TRUE(result.parts.empty());
  EXPECT_NE(result.message.find("opening"), std::string::npos) << result.message;
}

TEST(FillBin, AMeshBinWithoutVolumeIsRefused) {
  BinSpec bin = SmallFillBin();
  bin.mesh = test::SlopedTote(0.1f, 0.1f, 0.1f, 0.1f, 0.0f);
  EXPECT_EQ(FieldOf(bin, Mix(1, 1), FillOptions{}), "bin.mesh");
  bin.mesh = test::SlopedTote(0.1f, 0.1f, 0.2f, 0.2f, 0.1f);
  bin.mesh.vertices[5].x() = std::nanf("");
  EXPECT_EQ(FieldOf(bin, Mix(1, 1), FillOptions{}), "bin.mesh");
}

}  // namespace
}  // namespace vscan::physics
