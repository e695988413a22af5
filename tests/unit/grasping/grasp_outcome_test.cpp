#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "grasping/grasp_outcome.h"
#include "vscan_test/meshes.h"

namespace vscan::grasping {
namespace {

Pose3 Shift(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

const TriangleMesh& TrueBlock() {
  static const TriangleMesh block = test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02});
  return block;
}

// The planned top-face grasp at the block's centre, approach straight down.
Grasp TopCentre() {
  Grasp g;
  g.part_from_tool.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  g.part_from_tool.translation() = Eigen::Vector3d(0, 0, 0.02);
  g.approach = -Eigen::Vector3d::UnitZ();
  return g;
}

TEST(GraspOutcomeTest, ACupPlannedOnAnEstimateHoldsOnlyWhereTheTrueSurfaceMeetsIt) {
  SuctionCup cup;
  cup.diameter_m = 0.010;
  cup.stroke_m = 0.010;
  const auto target = GraspTarget::Make(TrueBlock(), cup);
  ASSERT_TRUE(target.ok()) << target.status().ToString();
  const Grasp g = TopCentre();
  // truth_from_estimate: where the estimated part frame lies in the true part's frame.
  EXPECT_TRUE((*target)->Try(g, Pose3::Identity()).holds);
  // Estimated 5 mm too low: the surface comes 5 mm early and the bellows take it up.
  const GraspOutcome early = (*target)->Try(g, Shift(0, 0, -0.005));
  EXPECT_TRUE(early.holds) << early.why;
  EXPECT_NEAR(early.contact_offset_m, -0.005, 1e-9);
  // Estimated 5 mm too high: the cup stops 5 mm short, beyond the 2 mm overtravel.
  const GraspOutcome short_of = (*target)->Try(g, Shift(0, 0, 0.005));
  EXPECT_FALSE(short_of.holds);
  EXPECT_EQ(short_of.why, "the cup meets no surface of the part");
  // 1.5 mm high is within the overtravel.
  EXPECT_TRUE((*target)->Try(g, Shift(0, 0, 0.0015)).holds);
  // 17 mm sideways the cup hangs over the edge; 30 mm it misses the part.
  const GraspOutcome edge = (*target)->Try(g, Shift(0.017, 0, 0));
  EXPECT_FALSE(edge.holds);
  EXPECT_NE(edge.why.find("seal"), std::string::npos) << edge.why;
  EXPECT_FALSE((*target)->Try(g, Shift(0.03, 0, 0)).holds);
  // A quarter turn about the vertical keeps the cup on the top face; 20 degrees of tilt does not
  // (the cup allows 10).
  Pose3 turned = Pose3::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_TRUE((*target)->Try(g, turned).holds);
  Pose3 tilted = Shift(0, 0, 0.02) * Pose3(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitX())) * Shift(0, 0, -0.02);
  const GraspOutcome tilt = (*target)->Try(g, tilted);
  EXPECT_FALSE(tilt.holds);
  EXPECT_EQ(tilt.why, "the surface tilts more than the cup allows");
}

TEST(GraspOutcomeTest, JawsPlannedOnAnEstimateCloseOnTheTruePartOrMissIt) {
  ParallelJaws jaws;
  jaws.min_opening_m = 0.002;
  jaws.max_opening_m = 0.035;
  const auto target = GraspTarget::Make(TrueBlock(), jaws);
  ASSERT_TRUE(target.ok()) << target.status().ToString();
  // Across the 30 mm side (closing along y), from above, at mid height.
  Grasp g;
  g.part_from_tool.linear() << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  g.part_from_tool.linear().col(2) = -Eigen::Vector3d::UnitZ();
  g.part_from_tool.linear().col(0) = Eigen::Vector3d::UnitY().cross(-Eigen::Vector3d::UnitZ());
  g.part_from_tool.translation() = Eigen::Vector3d(0, 0, 0.01);
  g.opening_m = 0.03;
  const GraspOutcome exact = (*target)->Try(g, Pose3::Identity());
  EXPECT_TRUE(exact.holds) << exact.why;
  EXPECT_NEAR(exact.contact_offset_m, 0.030, 1e-9);
  // 2 mm off along the closing axis the fingers still close on both faces.
  EXPECT_TRUE((*target)->Try(g, Shift(0, 0.002, 0)).holds);
  // 4 mm off one open finger (17.5 mm out) starts inside the 15 mm half-width + 4 mm.
  const GraspOutcome inside = (*target)->Try(g, Shift(0, 0.004, 0));
  EXPECT_FALSE(inside.holds);
  EXPECT_EQ(inside.why, "a finger lands on the part");
  // 25 mm off to the side along x: the fingers close on nothing.
  EXPECT_EQ((*target)->Try(g, Shift(0.025, 0, 0)).why, "a finger closes on nothing");
  // Turned 30 degrees about the vertical, the faces lie outside a 15 degree friction cone.
  Pose3 turned = Pose3::Identity();
  turned.linear() = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ((*target)->Try(g, turned).why, "a contact lies outside the friction cone");
}

TEST(GraspOutcomeTest, BadInputsAreRefusedNamingTheField) {
  SuctionCup cup;
  cup.diameter_m = std::nan("");
  EXPECT_EQ(GraspTarget::Make(TrueBlock(), cup).status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(GraspTarget::Make(TriangleMesh{}, SuctionCup{}).status().message().find("mesh"), std::string::npos);
  OutcomeOptions options;
  options.overtravel_m = 1e19;
  EXPECT_NE(GraspTarget::Make(TrueBlock(), SuctionCup{}, options).status().message().find("outcome_options.overtravel_m"),
            std::string::npos);
  const auto target = GraspTarget::Make(TrueBlock(), SuctionCup{});
  ASSERT_TRUE(target.ok());
  EXPECT_FALSE((*target)->Try(TopCentre(), Shift(std::nan(""), 0, 0)).holds);
}

}  // namespace
}  // namespace vscan::grasping
