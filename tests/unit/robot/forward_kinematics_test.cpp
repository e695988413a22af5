#include "robot/forward_kinematics.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "kdl_oracle.h"
#include "robot/urdf_bundle.h"
#include "robot/urdf_chain.h"
#include "robot_fixtures.h"

namespace vscan::robot {
namespace {

using testing::FixtureBundle;
using testing::FixtureChain;
using testing::KdlOracle;

double RotationAngle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// Max position and orientation difference from KDL over `samples` random configurations.
std::pair<double, double> MaxFkDifference(const KinematicChain& chain, const KdlOracle& kdl, int samples) {
  std::mt19937_64 rng(42);
  double position = 0.0, orientation = 0.0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::VectorXd q = RandomJointPositions(chain, rng);
    const Pose3 ours = ForwardKinematics(chain, q).value();
    const Pose3 theirs = kdl.Fk(q);
    position = std::max(position, (ours.translation() - theirs.translation()).norm());
    orientation = std::max(orientation, RotationAngle(ours.linear(), theirs.linear()));
  }
  return {position, orientation};
}

class FixtureFk : public ::testing::TestWithParam<std::string> {};

TEST_P(FixtureFk, MatchesKdlAt200RandomConfigurations) {
  const testing::FixtureRobot& robot = testing::Fixture(GetParam());
  const KinematicChain chain = FixtureChain(robot.name);
  const KdlOracle kdl(*FixtureBundle(robot.name).model, robot.base_link, robot.tip_link);
  ASSERT_EQ(kdl.dof(), chain.dof());
  const auto [position, orientation] = MaxFkDifference(chain, kdl, 200);
  EXPECT_LE(position, 1e-9);
  EXPECT_LE(orientation, 1e-9);
}

TEST_P(FixtureFk, JacobianMatchesKdl) {
  const testing::FixtureRobot& robot = testing::Fixture(GetParam());
  const KinematicChain chain = FixtureChain(robot.name);
  const KdlOracle kdl(*FixtureBundle(robot.name).model, robot.base_link, robot.tip_link);
  std::mt19937_64 rng(3);
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd q = RandomJointPositions(chain, rng);
    EXPECT_LE((GeometricJacobian(chain, q).value() - kdl.Jacobian(q)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, FixtureFk, ::testing::Values("ur5", "panda"));

TEST(ForwardKinematics, PrismaticContinuousAndSkewAxesMatchKdl) {
  const std::string urdf = R"(<robot name="r">
    <link name="a"/><link name="b"/><link name="c"/><link name="d"/><link name="e"/>
    <joint name="slide" type="prismatic"><parent link="a"/><child link="b"/>
      <origin xyz="0.1 0 0.2" rpy="0.1 0.2 0.3"/><axis xyz="1 1 0"/>
      <limit lower="-0.3" upper="0.4" effort="1" velocity="1"/></joint>
    <joint name="spin" type="continuous"><parent link="b"/><child link="c"/>
      <origin xyz="0 0.3 0" rpy="0 1.2 0"/><axis xyz="0.2 -0.5 0.8"/></joint>
    <joint name="bend" type="revolute"><parent link="c"/><child link="d"/>
      <origin xyz="0.25 0 0.05" rpy="-0.4 0 0.9"/><axis xyz="0 -1 0"/>
      <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
    <joint name="flange" type="fixed"><parent link="d"/><child link="e"/><origin xyz="0 0 0.1" rpy="0.5 0 0"/></joint>
  </robot>)";
  StatusOr<UrdfBundle> bundle = LoadUrdfBundle("r.urdf", {{"r.urdf", urdf}});
  ASSERT_TRUE(bundle.ok()) << bundle.status().ToString();
  StatusOr<KinematicChain> chain = BuildChain(*bundle->model, {"a", "e"});
  ASSERT_TRUE(chain.ok()) << chain.status().ToString();
  const KdlOracle kdl(*bundle->model, "a", "e");
  const auto [position, orientation] = MaxFkDifference(*chain, kdl, 200);
  EXPECT_LE(position, 1e-9);
  EXPECT_LE(orientation, 1e-9);
  std::mt19937_64 rng(5);
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd q = RandomJointPositions(*chain, rng);
    EXPECT_LE((GeometricJacobian(*chain, q).value() - kdl.Jacobian(q)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(ForwardKinematics, JacobianMatchesFiniteDifferences) {
  Pose3 tip_from_tool = Pose3::Identity();
  tip_from_tool.translation() = Eigen::Vector3d(0.05, -0.02, 0.2);
  for (const char* name : {"ur5", "panda"}) {
    const KinematicChain chain = FixtureChain(name, tip_from_tool);
    std::mt19937_64 rng(11);
    for (int s = 0; s < 20; ++s) {
      // Keep away from the limits so that q +- h stays valid.
      Eigen::VectorXd q = RandomJointPositions(chain, rng);
      q = 0.9 * q + 0.1 * chain.MidLimits();
      const Jacobian J = GeometricJacobian(chain, q).value();
      const double h = 1e-6;
      for (int i = 0; i < chain.dof(); ++i) {
        Eigen::VectorXd plus = q, minus = q;
        plus[i] += h;
        minus[i] -= h;
        const Pose3 Tp = ForwardKinematics(chain, plus).value();
        const Pose3 Tm = ForwardKinematics(chain, minus).value();
        const Eigen::Vector3d v = (Tp.translation() - Tm.translation()) / (2 * h);
        const Eigen::AngleAxisd w(Tp.linear() * Tm.linear().transpose());
        const Eigen::Vector3d omega = w.axis() * w.angle() / (2 * h);
        EXPECT_LE((J.col(i).head<3>() - v).norm(), 1e-7) << name << " joint " << i;
        EXPECT_LE((J.col(i).tail<3>() - omega).norm(), 1e-7) << name << " joint " << i;
      }
    }
  }
}

TEST(ForwardKinematics, RejectsBadJointPositions) {
  const KinematicChain chain = FixtureChain("panda");
  Eigen::VectorXd q = chain.MidLimits();
  EXPECT_EQ(ForwardKinematics(chain, Eigen::VectorXd::Zero(6)).status().code(), StatusCode::kInvalidArgument);
  q[2] = std::numeric_limits<double>::quiet_NaN();
  StatusOr<Pose3> nan = ForwardKinematics(chain, q);
  EXPECT_EQ(nan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(nan.status().message().rfind("joint_positions[2]: ", 0), 0u) << nan.status().message();
  q = chain.MidLimits();
  q[3] = 0.5;  // panda_joint4 lives in [-3.0718, -0.0698]
  StatusOr<Pose3> outside = ForwardKinematics(chain, q);
  EXPECT_EQ(outside.status().code(), StatusCode::kOutOfRange);
  EXPECT_EQ(outside.status().message().rfind("joint_positions[3]: 0.5 outside [-3.0718, -0.0698]", 0), 0u)
      << outside.status().message();
  EXPECT_EQ(GeometricJacobian(chain, q).status().code(), StatusCode::kOutOfRange);
}

TEST(ForwardKinematics, LinkPosesEndAtTheTip) {
  const KinematicChain chain = FixtureChain("ur5");
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(6, -1.0, 1.0);
  const std::vector<LinkPose> poses = ChainLinkPoses(chain, q).value();
  ASSERT_EQ(poses.size(), chain.segments().size() + 1);
  EXPECT_EQ(poses.front().link, "base_link");
  EXPECT_EQ(poses.back().link, "tool0");
  EXPECT_TRUE(poses.back().base_from_link.isApprox(ForwardKinematics(chain, q).value(), 1e-12));
}

}  // namespace
}  // namespace vscan::robot
