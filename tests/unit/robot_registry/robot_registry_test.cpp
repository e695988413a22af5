#include "robot_registry/robot_registry.h"

#include <gtest/gtest.h>

#include <random>

#include "vscan_test/temp_dir.h"
#include "robot/forward_kinematics.h"
#include "robot_fixtures.h"
#include "store/catalogue.h"

namespace vscan::robot_registry {
namespace {

Pose3 Tool() {
  Pose3 tool = Pose3::Identity();
  tool.translate(Eigen::Vector3d(0.0, 0.02, 0.05));
  tool.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  return tool;
}

Pose3 Base() {
  Pose3 base = Pose3::Identity();
  base.translate(Eigen::Vector3d(0.3, -0.2, 0.1));
  base.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  return base;
}

RobotUpload PandaUpload() {
  const auto& fixture = robot::testing::Fixture("panda");
  RobotUpload upload;
  upload.urdf_path = fixture.urdf_path;
  upload.base_link = fixture.base_link;
  upload.tip_link = fixture.tip_link;
  upload.tip_from_tool = Tool();
  upload.files = robot::testing::FixtureBundleFiles("panda");
  return upload;
}

class RobotRegistryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scenes_ = std::move(store::Catalogue::Open(dir_.path() / "db.sqlite")).value();
    catalogue_ = std::move(store::RobotCatalogue::Open(dir_.path() / "db.sqlite")).value();
    blobs_ = std::make_unique<store::BlobStore>(dir_.path() / "blobs");
    ASSERT_TRUE(blobs_->Open().ok());
    registry_ = std::make_unique<RobotRegistry>(*catalogue_, *blobs_, 64u << 20);
  }

  test::TempDir dir_;
  std::unique_ptr<store::Catalogue> scenes_;
  std::unique_ptr<store::RobotCatalogue> catalogue_;
  std::unique_ptr<store::BlobStore> blobs_;
  std::unique_ptr<RobotRegistry> registry_;
};

TEST_F(RobotRegistryTest, StoredChainMatchesTheEngine) {
  auto robot = registry_->AddRobot(PandaUpload());
  ASSERT_TRUE(robot.ok()) << robot.status().ToString();
  EXPECT_EQ(robot->name, "panda");
  EXPECT_EQ(robot->joints.size(), 7u);
  EXPECT_FALSE(robot->warnings.empty());
  EXPECT_TRUE(blobs_->Contains(robot->bundle_sha256));

  // A fresh registry has to rebuild the chain from the stored bundle.
  RobotRegistry fresh(*catalogue_, *blobs_, 64u << 20);
  auto chain = fresh.Chain(robot->robot_id);
  ASSERT_TRUE(chain.ok()) << chain.status().ToString();
  const robot::KinematicChain expected = robot::testing::FixtureChain("panda", Tool());
  std::mt19937_64 rng(3);
  for (int i = 0; i < 20; ++i) {
    const Eigen::VectorXd q = robot::RandomJointPositions(expected, rng);
    EXPECT_TRUE((*robot::ForwardKinematics(**chain, q)).isApprox(*robot::ForwardKinematics(expected, q), 1e-12));
  }
}

TEST_F(RobotRegistryTest, MountedKinematicsWorkInTheWorld) {
  auto robot = registry_->AddRobot(PandaUpload());
  auto scene = scenes_->CreateScene("cell");
  ASSERT_TRUE(robot.ok() && scene.ok());
  store::MountRecord record;
  record.scene_id = scene->scene_id;
  record.robot_id = robot->robot_id;
  record.base_pose = Base().matrix();
  record.encoder_sigma = {0.01};
  auto added = registry_->AddMount(record);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  EXPECT_EQ(added->first.encoder_sigma.size(), 7u);
  auto mounted = registry_->Mount(added->first.mount_id);
  ASSERT_TRUE(mounted.ok());

  const robot::KinematicChain chain = robot::testing::FixtureChain("panda", Tool());
  Eigen::VectorXd q = chain.MidLimits();
  q[1] = -0.3;
  auto state = CommandJoints(*mounted->chain, mounted->placement, q, "q");
  ASSERT_TRUE(state.ok());
  EXPECT_TRUE(state->commanded_pose.isApprox(Base() * *robot::ForwardKinematics(chain, q), 1e-12));
  EXPECT_EQ(state->achieved, q);

  auto noisy = CommandJoints(*mounted->chain, mounted->placement, q, "q", 9);
  auto again = CommandJoints(*mounted->chain, mounted->placement, q, "q", 9);
  ASSERT_TRUE(noisy.ok() && again.ok());
  EXPECT_GT((noisy->achieved - q).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_EQ(noisy->achieved, again->achieved);
  EXPECT_TRUE(noisy->commanded_pose.isApprox(state->commanded_pose));

  const robot::IkGoal goal = robot::PoseGoal(state->commanded_pose);
  auto answer = SolveInPlacement(*mounted->chain, mounted->placement, goal, Eigen::VectorXd(), IkSettings{});
  ASSERT_TRUE(answer.ok()) << answer.status().ToString();
  EXPECT_TRUE(answer->reached);
  EXPECT_LT((answer->frame_from_tool.translation() - state->commanded_pose.translation()).norm(), 1e-5);

  const robot::IkGoal far = robot::PositionGoal(Base() * Eigen::Vector3d(3.0, 0.0, 0.3));
  auto miss = SolveInPlacement(*mounted->chain, mounted->placement, far, Eigen::VectorXd(), IkSettings{});
  ASSERT_TRUE(miss.ok());
  EXPECT_FALSE(miss->reached);
  EXPECT_GT(miss->miss_distance, 1.5);
  EXPECT_NE(miss->failure.message().find("misses by"), std::string::npos);
  EXPECT_NE(miss->failure.message().find("nearest reachable tool pose"), std::string::npos);
}

TEST_F(RobotRegistryTest, BadUploadsChangeNothing) {
  RobotUpload escaping = PandaUpload();
  escaping.files.push_back({"../outside.stl", "x"});
  auto refused = registry_->AddRobot(std::move(escaping));
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("files["), std::string::npos);

  RobotUpload unknown_tip = PandaUpload();
  unknown_tip.tip_link = "nope";
  refused = registry_->AddRobot(std::move(unknown_tip));
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(refused.status().message().rfind("header.tip_link", 0), 0u);

  RobotRegistry tiny(*catalogue_, *blobs_, 1000);
  EXPECT_EQ(tiny.AddRobot(PandaUpload()).status().code(), StatusCode::kResourceExhausted);
  EXPECT_TRUE(catalogue_->ListRobots("", 10)->empty());
}

TEST_F(RobotRegistryTest, DeletingTheLastUserRemovesTheBundle) {
  auto a = registry_->AddRobot(PandaUpload());
  auto b = registry_->AddRobot(PandaUpload());
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->bundle_sha256, b->bundle_sha256);
  ASSERT_TRUE(registry_->DeleteRobot(a->robot_id).ok());
  EXPECT_TRUE(blobs_->Contains(b->bundle_sha256));
  EXPECT_TRUE(registry_->Chain(b->robot_id).ok());
  ASSERT_TRUE(registry_->DeleteRobot(b->robot_id).ok());
  EXPECT_FALSE(blobs_->Contains(b->bundle_sha256));
  EXPECT_EQ(registry_->Chain(b->robot_id).status().code(), StatusCode::kNotFound);
}

}  // namespace
}  // namespace vscan::robot_registry
