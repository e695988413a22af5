#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "box_overlap.h"
#include "grasp_shapes.h"
#include "grasping/pick_checks.h"
#include "vscan_test/meshes.h"

namespace vscan::grasping {
namespace {

const Eigen::Vector3d kDown(0, 0, -1);

Pose3 At(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

// A 40 x 30 x 20 mm box with its frame at the centre of its bottom face.
std::shared_ptr<const TriangleMesh> Block() { return test::Share(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02})); }

PlacedMesh Floor() { return {test::Share(test::MakeBox({-0.5, -0.5, -0.01}, {0.5, 0.5, 0})), Pose3::Identity()}; }

std::vector<Grasp> Grasps(const TriangleMesh& mesh, const Gripper& gripper) {
  GraspOptions options;
  options.max_grasps = 100000;
  auto grasps = GenerateGrasps(mesh, gripper, options);
  EXPECT_TRUE(grasps.ok()) << grasps.status().ToString();
  return grasps.ok() ? *grasps : std::vector<Grasp>{};
}

std::vector<ConvexPiece> Sweep(const Gripper& gripper, const ToolSweep& sweep = {}) {
  std::vector<ConvexPiece> out;
  for (const TriangleMesh& piece : GripperSweep(gripper, sweep)) out.emplace_back(piece);
  return out;
}

SuctionCup Cup(double diameter) {
  SuctionCup cup;
  cup.diameter_m = diameter;
  return cup;
}

ParallelJaws Jaws() {
  ParallelJaws jaws;
  jaws.min_opening_m = 0.002;
  jaws.max_opening_m = 0.035;
  jaws.finger_width_m = 0.008;
  jaws.finger_depth_m = 0.008;
  return jaws;
}

TEST(PickChecksTest, EveryTopFaceSuctionGraspOfABoxAloneOnAFloorIsPickable) {
  const auto block = Block();
  const Gripper cup = Cup(0.010);
  const std::vector<std::vector<Grasp>> grasps{Grasps(*block, cup)};
  Pile pile;
  pile.parts.push_back({0, block, At(0.1, 0.05, 0)});
  pile.fixtures.push_back(Floor());
  const auto sweep = Sweep(cup);
  size_t top = 0;
  for (const Grasp& g : grasps[0]) {
    const Pose3 world_from_tool = pile.parts[0].world_from_part * g.part_from_tool;
    if (world_from_tool.linear().col(2).dot(kDown) < 1 - 1e-9) continue;
    ++top;
    EXPECT_FALSE(FindSweepContact(pile, 0, sweep, world_from_tool).has_value());
  }
  EXPECT_GT(top, 10u);

  const auto verdicts = CheckPicks(pile, grasps, cup, {}, {});
  ASSERT_TRUE(verdicts.ok()) << verdicts.status().ToString();
  ASSERT_EQ(verdicts->size(), 1u);
  const PickVerdict& v = (*verdicts)[0];
  EXPECT_TRUE(v.pickable) << v.detail;
  ASSERT_TRUE(v.grasp.has_value());
  EXPECT_NEAR(v.world_from_tool.linear().col(2).dot(kDown), 1, 1e-9);
  EXPECT_NEAR(v.world_from_tool.translation().z(), 0.02, 1e-6);
  // Side and bottom grasps come before it in quality order but not from above.
  EXPECT_EQ(v.grasps_from_above, 1u);
}

TEST(PickChecksTest, APartUnderAnotherIsCoveredAndTheOneOnTopIsPickable) {
  const auto block = Block();
  const Gripper cup = Cup(0.010);
  const std::vector<std::vector<Grasp>> grasps{Grasps(*block, cup)};
  Pile pile;
  pile.parts.push_back({0, block, At(0, 0, 0)});
  pile.parts.push_back({0, block, At(0.015, 0.005, 0.0203)});  // resting on it, 0.3 mm above, overhanging
  pile.parts.push_back({0, block, At(0.2, 0, 0)});             // alone, far away
  pile.fixtures.push_back(Floor());
  const auto verdicts = CheckPicks(pile, grasps, cup, {}, {});
  ASSERT_TRUE(verdicts.ok()) << verdicts.status().ToString();
  EXPECT_FALSE((*verdicts)[0].pickable);
  EXPECT_EQ((*verdicts)[0].failure, PickFailure::kCovered);
  EXPECT_EQ((*verdicts)[0].covered_by, std::optional<PileItem>(PileItem{false, 1}));
  EXPECT_TRUE((*verdicts)[1].pickable) << (*verdicts)[1].detail;
  EXPECT_TRUE((*verdicts)[2].pickable) << (*verdicts)[2].detail;
  // A fixture (a bar) resting on a part covers it too.
  Pile under_bar = pile;
  under_bar.fixtures.push_back({test::Share(test::MakeBox({0.18, -0.05, 0.0205}, {0.22, 0.05, 0.03})), Pose3::Identity()});
  const auto barred = CheckPicks(under_bar, grasps, cup, {}, {});
  ASSERT_TRUE(barred.ok());
  EXPECT_EQ((*barred)[2].failure, PickFailure::kCovered);
  EXPECT_EQ((*barred)[2].covered_by, std::optional<PileItem>(PileItem{true, 1}));
  EXPECT_EQ((*barred)[2].detail, "fixture 1 lies on it");
  // A wall 1 mm taller than it, pressed 2 mm into it, does not cover it (rays start inside the wall).
  Pile walled = pile;
  walled.fixtures.push_back({test::Share(test::MakeBox({0.218, -0.1, 0}, {0.23, 0.1, 0.021})), Pose3::Identity()});
  const auto beside = CheckPicks(walled, grasps, cup, {}, {});
  ASSERT_TRUE(beside.ok());
  EXPECT_NE((*beside)[2].failure, PickFailure::kCovered) << (*beside)[2].detail;
  // Lifted 5 mm clear of it, the upper block no longer covers the lower one.
  pile.parts[1].world_from_part = At(0.015, 0.005, 0.025);
  const auto apart = CheckPicks(pile, grasps, cup, {}, {});
  ASSERT_TRUE(apart.ok());
  EXPECT_NE((*apart)[0].failure, PickFailure::kCovered);
}

TEST(PickChecksTest, AThinWalledBoxLyingOnAnotherIsNotCoveredByIt) {
  // Hollow boxes with 0.4 mm walls (thinner than the depth cover rays start at): the one below is
  // covered, the one on top is not, although its cavity's floor faces up above the lower box.
  const double wall = 0.0004;
  const auto hollow = test::Share(testing::Join(test::MakeBox({-0.02, -0.01, 0}, {0.02, 0.01, 0.01}),
                                                testing::Flipped(test::MakeBox({-0.02 + wall, -0.01 + wall, wall},
                                                                               {0.02 - wall, 0.01 - wall, 0.01 - wall}))));
  const Gripper cup = Cup(0.006);
  const std::vector<std::vector<Grasp>> grasps{Grasps(*hollow, cup)};
  Pile pile;
  pile.parts.push_back({0, hollow, At(0, 0, 0)});
  pile.parts.push_back({0, hollow, At(0.005, 0.002, 0.0101)});
  pile.fixtures.push_back(Floor());
  const auto verdicts = CheckPicks(pile, grasps, cup, {}, {});
  ASSERT_TRUE(verdicts.ok()) << verdicts.status().ToString();
  EXPECT_EQ((*verdicts)[0].failure, PickFailure::kCovered);
  EXPECT_NE((*verdicts)[1].failure, PickFailure::kCovered) << (*verdicts)[1].detail;
}

TEST(PickChecksTest, ACupUnderAnOverhangingBarCollidesExactlyWhereItsColumnReachesTheBar) {
  const auto block = Block();
  const double radius = 0.010;
  const SuctionCup cup = Cup(2 * radius);
  const std::vector<std::vector<Grasp>> grasps{Grasps(*block, cup)};
  Pile pile;
  pile.parts.push_back({0, block, Pose3::Identity()});
  // A bar 15 mm above the block's top from x = 12 mm on: the cup's column meets it when its
  // disc reaches past x = 12 mm.
  const double wall_x = 0.012;
  pile.fixtures.push_back(Floor());
  pile.fixtures.push_back({test::Share(test::MakeBox({wall_x, -0.1, 0.035}, {0.2, 0.1, 0.045})), Pose3::Identity()});
  const auto sweep = Sweep(cup);
  size_t hit = 0, clear = 0;
  double farthest = -1;
  for (const Grasp& g : grasps[0]) {
    if (g.part_from_tool.linear().col(2).dot(kDown) < 1 - 1e-9) continue;
    farthest = std::max(farthest, g.part_from_tool.translation().x());
    const double reach = g.part_from_tool.translation().x() + radius;  // the disc's farthest x
    if (std::abs(reach - wall_x) < 0.0003) continue;  // the circumscribed prism is up to 0.09 mm wider
    const auto contact = FindSweepContact(pile, 0, sweep, g.part_from_tool);
    EXPECT_EQ(contact.has_value(), reach > wall_x) << "cup centre x " << g.part_from_tool.translation().x();
    if (contact) {
      EXPECT_EQ(*contact, (PileItem{true, 1}));
      ++hit;
    } else {
      ++clear;
    }
  }
  EXPECT_GT(hit, 3u) << "farthest cup centre x " << farthest;
  EXPECT_GT(clear, 3u);
}

TEST(PickChecksTest, JawSweepVerdictsAgreeWithAnExactTriangleBoxTestOnRandomNeighbours) {
  // A separate formulation: every triangle of a twelve-sided prism against the sweep's boxes as
  // axis-aligned boxes. Placements within 0.2 mm of touching are ambiguous and skipped.
  const ParallelJaws jaws = Jaws();
  const ToolSweep tool{0.06, 0.03};
  const auto sweep = Sweep(jaws, tool);
  const auto prism = test::Share(testing::MakeCylinder(0.008, 0.03, 12));
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;
  for (const auto& piece : GripperSweep(jaws, tool)) {
    Eigen::Vector3f lo, hi;
    piece.Bounds(lo, hi);
    boxes.emplace_back(lo.cast<double>(), hi.cast<double>());
  }
  Pile pile;
  pile.parts.push_back({0, Block(), At(1, 1, 1)});  // the grasped part, far away
  pile.parts.push_back({0, prism, Pose3::Identity()});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coord(-0.045, 0.045), depth(-0.14, 0.03), turn(-1, 1);
  int meets = 0, misses = 0, agreed = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Pose3 pose = At(coord(rng), coord(rng), depth(rng));
    pose.linear() = Eigen::Quaterniond(Eigen::Vector4d(turn(rng), turn(rng), turn(rng), turn(rng)).normalized())
                        .toRotationMatrix();
    pile.parts[1].world_from_part = pose;
    bool inner = false, outer = false;
    for (const auto& [lo, hi] : boxes) {
      const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.0002);
      inner = inner || testing::MeshMeetsBox(*prism, pose, lo + margin, hi - margin);
      outer = outer || testing::MeshMeetsBox(*prism, pose, lo - margin, hi + margin);
    }
    if (inner != outer) continue;
    const bool contact = FindSweepContact(pile, 0, sweep, Pose3::Identity()).has_value();
    EXPECT_EQ(contact, inner) << "trial " << trial;
    agreed += contact == inner;
    (inner ? meets : misses)++;
  }
  EXPECT_GT(meets, 30);
  EXPECT_GT(misses, 30);
  EXPECT_EQ(agreed, meets + misses);
}

TEST(PickChecksTest, JawsNearTheFloorHitItAndTheArmsAnswerDecidesTheRest) {
  const auto block = Block();
  const ParallelJaws jaws = Jaws();
  const std::vector<std::vector<Grasp>> grasps{Grasps(*block, jaws)};
  Pile pile;
  pile.parts.push_back({0, block, Pose3::Identity()});
  pile.fixtures.push_back(Floor());
  const auto sweep = Sweep(jaws);
  size_t low = 0, high = 0;
  for (const Grasp& g : grasps[0]) {
    if (g.part_from_tool.linear().col(2).dot(kDown) < 1 - 1e-9) continue;
    // The pads reach finger_depth / 2 below the tool centre; the floor is at z = 0.
    const double tip = g.part_from_tool.translation().z() - jaws.finger_depth_m / 2;
    if (std::abs(tip) < 0.0003) continue;
    EXPECT_EQ(FindSweepContact(pile, 0, sweep, g.part_from_tool).has_value(), tip < 0);
    (tip < 0 ? low : high)++;
  }
  EXPECT_GT(low, 0u);
  EXPECT_GT(high, 0u);

  PickOptions options;
  options.max_reach_checks = 5;
  size_t asked = 0;
  const ReachCheck never = [&](const Pose3& tool, const Pose3&) -> StatusOr<ReachAnswer> {
    ++asked;
    EXPECT_GE(tool.linear().col(2).dot(kDown), 0.5 - 1e-9);  // within the default 60 degrees
    return ReachAnswer{PickFailure::kUnreachable, "misses by 0.3 m", {}};
  };
  auto verdicts = CheckPicks(pile, grasps, jaws, options, never);
  ASSERT_TRUE(verdicts.ok()) << verdicts.status().ToString();
  EXPECT_FALSE((*verdicts)[0].pickable);
  EXPECT_EQ((*verdicts)[0].failure, PickFailure::kUnreachable);
  EXPECT_EQ((*verdicts)[0].detail, "misses by 0.3 m");
  EXPECT_EQ((*verdicts)[0].reach_checks, 5u);
  EXPECT_EQ(asked, 5u);

  // An arm that reaches only tools on the part's +x side: the verdict's grasp is one of those,
  // and its pre-grasp stands 50 mm back along the approach.
  const ReachCheck plus_x = [](const Pose3& tool, const Pose3& pregrasp) -> StatusOr<ReachAnswer> {
    EXPECT_NEAR((pregrasp.translation() - tool.translation()).dot(tool.linear().col(2)), -0.05, 1e-9);
    if (tool.translation().x() > 0.001) return ReachAnswer{PickFailure::kNone, "", Eigen::VectorXd::Ones(6)};
    return ReachAnswer{PickFailure::kArmCollision, "link 'wrist' touches the bin", {}};
  };
  options.max_reach_checks = 1000;
  verdicts = CheckPicks(pile, grasps, jaws, options, plus_x);
  ASSERT_TRUE(verdicts.ok());
  ASSERT_TRUE((*verdicts)[0].pickable) << (*verdicts)[0].detail;
  EXPECT_GT((*verdicts)[0].world_from_tool.translation().x(), 0.001);
  EXPECT_EQ((*verdicts)[0].joint_positions.size(), 6);
}

TEST(PickChecksTest, BadPilesAndOptionsAreRefusedNamingTheField) {
  const auto block = Block();
  const Gripper cup = Cup(0.010);
  const std::vector<std::vector<Grasp>> grasps{{}};
  const auto field = [&](const Pile& pile, const PickOptions& options) {
    const auto result = CheckPicks(pile, grasps, cup, options, {});
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
    return result.status().message();
  };
  Pile pile;
  pile.parts.push_back({1, block, Pose3::Identity()});
  EXPECT_NE(field(pile, {}).find("pile.parts[0].type"), std::string::npos);
  pile.parts[0] = {0, nullptr, Pose3::Identity()};
  EXPECT_NE(field(pile, {}).find("pile.parts[0].mesh"), std::string::npos);
  pile.parts[0] = {0, block, At(std::nan(""), 0, 0)};
  EXPECT_NE(field(pile, {}).find("pile.parts[0].pose"), std::string::npos);
  pile.parts[0] = {0, block, Pose3::Identity()};
  PickOptions options;
  options.max_approach_tilt_deg = std::nan("");
  EXPECT_NE(field(pile, options).find("pick_options.max_approach_tilt_deg"), std::string::npos);
  options = {};
  options.sweep.approach_m = 1e19;
  EXPECT_NE(field(pile, options).find("pick_options.approach_m"), std::string::npos);
  options = {};
  options.cover_samples = 0;
  EXPECT_NE(field(pile, options).find("pick_options.cover_samples"), std::string::npos);
  pile.up = Eigen::Vector3d::Zero();
  EXPECT_NE(field(pile, {}).find("pile.up"), std::string::npos);
  // More than 1e6 grasps over the parts at worst: refused before any work.
  Pile many;
  for (int i = 0; i < 1001; ++i) many.parts.push_back({0, block, At(0.1 * i, 0, 0)});
  const std::vector<std::vector<Grasp>> thousand{std::vector<Grasp>(1000)};
  const auto refused = CheckPicks(many, thousand, cup, {}, {});
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(refused.status().message().find("grasp_options.max_grasps"), std::string::npos);
  // A part without grasps is not pickable, and says so.
  pile.up = Eigen::Vector3d::UnitZ();
  const auto none = CheckPicks(pile, grasps, cup, {}, {});
  ASSERT_TRUE(none.ok());
  EXPECT_EQ((*none)[0].failure, PickFailure::kNoGrasp);
}

}  // namespace
}  // namespace vscan::grasping
