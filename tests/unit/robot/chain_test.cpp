#include "robot/chain.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot/reach.h"
#include "robot/urdf_bundle.h"
#include "robot/urdf_chain.h"
#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

using testing::FixtureBundle;
using testing::FixtureChain;

TEST(Chain, Ur5HasSixJointsWithUrdfLimits) {
  const KinematicChain chain = FixtureChain("ur5");
  ASSERT_EQ(chain.dof(), 6);
  EXPECT_EQ(chain.base_link(), "base_link");
  EXPECT_EQ(chain.tip_link(), "tool0");
  EXPECT_EQ(chain.joints()[0].name, "shoulder_pan_joint");
  EXPECT_EQ(chain.joints()[5].name, "wrist_3_joint");
  EXPECT_NEAR(chain.joints()[2].lower, -std::numbers::pi, 1e-9);
  EXPECT_NEAR(chain.joints()[0].upper, 2 * std::numbers::pi, 1e-9);
  EXPECT_EQ(chain.segments().back().type, JointType::kFixed);
  EXPECT_EQ(chain.MidLimits(), Eigen::VectorXd::Zero(6));
}

TEST(Chain, PandaHasSevenJointsAndAsymmetricLimits) {
  const KinematicChain chain = FixtureChain("panda");
  ASSERT_EQ(chain.dof(), 7);
  EXPECT_DOUBLE_EQ(chain.joints()[3].lower, -3.0718);
  EXPECT_DOUBLE_EQ(chain.joints()[3].upper, -0.0698);
  EXPECT_DOUBLE_EQ(chain.MidLimits()[5], 0.5 * (-0.0175 + 3.7525));
}

TEST(Chain, UnknownLinksAreNotFound) {
  const auto& model = *FixtureBundle("ur5").model;
  StatusOr<KinematicChain> bad_base = BuildChain(model, {"nope", "tool0"});
  EXPECT_EQ(bad_base.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(bad_base.status().message(), "base_link: no link 'nope'");
  EXPECT_EQ(BuildChain(model, {"base_link", "nope"}).status().code(), StatusCode::kNotFound);
}

TEST(Chain, TipMustBeBelowBase) {
  const auto& model = *FixtureBundle("ur5").model;
  StatusOr<KinematicChain> reversed = BuildChain(model, {"tool0", "base_link"});
  EXPECT_EQ(reversed.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(reversed.status().message().find("not below"), std::string::npos) << reversed.status().message();
  EXPECT_EQ(BuildChain(model, {"base_link", "base_link"}).status().code(), StatusCode::kInvalidArgument);
}

TEST(Chain, DefaultTipMustBeUnambiguous) {
  // The UR5 ends in two sibling leaves (ee_link, tool0); the Panda in its fingers and TCP.
  for (const char* name : {"ur5", "panda"}) {
    StatusOr<KinematicChain> chain = BuildChain(*FixtureBundle(name).model, {});
    EXPECT_EQ(chain.status().code(), StatusCode::kInvalidArgument) << name;
    EXPECT_NE(chain.status().message().find("tip_link"), std::string::npos) << chain.status().message();
  }
  // Below panda_link0 up to panda_link8 there is one deepest link once the tip is named.
  EXPECT_TRUE(BuildChain(*FixtureBundle("panda").model, {"", "panda_link8"}).ok());
}

TEST(Chain, DefaultTipIsTheSingleDeepestLink) {
  const std::string urdf = R"(<robot name="r"><link name="a"/><link name="b"/><link name="c"/><link name="d"/>
    <joint name="ab" type="continuous"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/></joint>
    <joint name="bc" type="prismatic"><parent link="b"/><child link="c"/><axis xyz="0 0 1"/>
      <limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
    <joint name="ad" type="fixed"><parent link="a"/><child link="d"/></joint></robot>)";
  StatusOr<UrdfBundle> bundle = LoadUrdfBundle("r.urdf", {{"r.urdf", urdf}});
  ASSERT_TRUE(bundle.ok()) << bundle.status().ToString();
  StatusOr<KinematicChain> chain = BuildChain(*bundle->model, {});
  ASSERT_TRUE(chain.ok()) << chain.status().ToString();
  EXPECT_EQ(chain->base_link(), "a");
  EXPECT_EQ(chain->tip_link(), "c");
  EXPECT_EQ(chain->joints()[0].type, JointType::kContinuous);
  EXPECT_TRUE(std::isinf(chain->joints()[0].upper));
  EXPECT_DOUBLE_EQ(chain->joints()[0].sample_upper, std::numbers::pi);
  EXPECT_EQ(chain->joints()[1].type, JointType::kPrismatic);
  // Reach: prismatic travel counts in the bound.
  EXPECT_DOUBLE_EQ(ReachUpperBound(*chain), 0.5);
}

TEST(Chain, ToolOffsetIsAppliedAfterTheTip) {
  Pose3 tip_from_tool = Pose3::Identity();
  tip_from_tool.translation() = Eigen::Vector3d(0.01, 0.02, 0.15);
  tip_from_tool.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const KinematicChain bare = FixtureChain("panda");
  const KinematicChain tooled = bare.WithTool(tip_from_tool);
  const Eigen::VectorXd q = bare.MidLimits();
  const Pose3 expected = ForwardKinematics(bare, q).value() * tip_from_tool;
  EXPECT_TRUE(ForwardKinematics(tooled, q).value().isApprox(expected, 1e-12));
}

TEST(Chain, SampledReachIsBelowTheUpperBound) {
  for (const char* name : {"ur5", "panda"}) {
    const KinematicChain chain = FixtureChain(name);
    const double bound = ReachUpperBound(chain);
    const double sampled = SampledReach(chain, 20000, 7);
    EXPECT_LE(sampled, bound) << name;
    EXPECT_GT(sampled, 0.6 * bound) << name;
  }
  // UR5 with tool0: upper arm 0.425 + forearm 0.39225 + wrist offsets; published reach 0.85 m.
  EXPECT_NEAR(SampledReach(FixtureChain("ur5"), 20000, 7), 0.95, 0.1);
}

TEST(Chain, ReachUpperBoundSumsWhatFollowsTheFirstJoint) {
  Pose3 before_first = Pose3::Identity(), offset = Pose3::Identity(), slide_origin = Pose3::Identity();
  before_first.translation() = Eigen::Vector3d(1, 0, 0);  // moves the first joint, not the reach
  offset.translation() = Eigen::Vector3d(0, 0.3, 0.4);
  offset.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()).toRotationMatrix();
  slide_origin.translation() = Eigen::Vector3d(0, 0, 0.2);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  std::vector<ChainSegment> segments = {
      {"j1", "a", "b", JointType::kRevolute, before_first, z, -1, 1},
      {"j2", "b", "c", JointType::kContinuous, offset, Eigen::Vector3d::UnitY(), 0, 0},
      {"j3", "c", "d", JointType::kPrismatic, slide_origin, z, -0.3, 0.1},
  };
  Pose3 tool = Pose3::Identity();
  tool.translation() = Eigen::Vector3d(0, 0.1, 0);
  const KinematicChain chain = ChainFromSegments("a", segments, tool).value();
  EXPECT_EQ(FirstJointOrigin(chain), Eigen::Vector3d(1, 0, 0));
  EXPECT_NEAR(ReachUpperBound(chain), 0.5 + 0.2 + 0.3 + 0.1, 1e-12);
  EXPECT_LE(SampledReach(chain, 5000, 1), ReachUpperBound(chain));
  double miss = 0;
  const Status status = CheckWithinReach(chain, Eigen::Vector3d(1, 0, 3.1), "goal", &miss);
  EXPECT_EQ(status.code(), StatusCode::kOutOfRange);
  EXPECT_NEAR(miss, 2.0, 1e-12);
  EXPECT_TRUE(CheckWithinReach(chain, Eigen::Vector3d(1, 0, 1.0), "goal").ok());
}

TEST(Chain, ClampToLimits) {
  const KinematicChain chain = FixtureChain("panda");
  Eigen::VectorXd q = Eigen::VectorXd::Constant(7, 10.0);
  q = ClampToLimits(chain, q);
  EXPECT_EQ(q, chain.UpperLimits());
}

TEST(Chain, SegmentsMustConnect) {
  ChainSegment s1{"j1", "a", "b", JointType::kRevolute, Pose3::Identity(), Eigen::Vector3d::UnitZ(), -1, 1};
  ChainSegment s2{"j2", "x", "c", JointType::kRevolute, Pose3::Identity(), Eigen::Vector3d::UnitZ(), -1, 1};
  EXPECT_EQ(ChainFromSegments("a", {s1, s2}).status().code(), StatusCode::kInvalidArgument);
  s2.parent_link = "b";
  s2.axis.setZero();
  EXPECT_EQ(ChainFromSegments("a", {s1, s2}).status().code(), StatusCode::kInvalidArgument);
  s2.axis = Eigen::Vector3d(0, 3, 4);
  s2.lower = 2;
  EXPECT_EQ(ChainFromSegments("a", {s1, s2}).status().code(), StatusCode::kInvalidArgument);
  s2.lower = -2;
  StatusOr<KinematicChain> chain = ChainFromSegments("a", {s1, s2});
  ASSERT_TRUE(chain.ok());
  EXPECT_DOUBLE_EQ(chain->joints()[1].axis.norm(), 1.0);
  EXPECT_EQ(chain->joints()[1].axis_index, -1);
}

}  // namespace
}  // namespace vscan::robot
