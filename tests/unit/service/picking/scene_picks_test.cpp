#include <gtest/gtest.h>

#include "robot/forward_kinematics.h"
#include "robot_registry/robot_registry.h"
#include "service/picking/scene_picks.h"
#include "service_world.h"
#include "vscan_test/meshes.h"

namespace vscan::service {
namespace {

Pose3 At(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

// A scene with a floor, a UR5 standing on a 0.2 m pedestal at the origin, and 40 x 30 x 20 mm
// blocks labelled as a bin fill labels its parts.
class ScenePicksTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = world_.SceneWith(testing::FloorSquare(1.0), Pose3::Identity());
    block_mesh_ = world_.AddMesh(test::MakeBox({-0.02, -0.015, 0}, {0.02, 0.015, 0.02}), "block");
    mount_ = world_.Mount("ur5", scene_, At(0, 0, 0.2));
  }

  std::string AddBlock(const Pose3& pose, const std::string& label) {
    store::ObjectRecord object;
    object.scene_id = scene_;
    object.mesh_id = block_mesh_;
    object.label = label;
    object.pose = pose.matrix();
    auto added = world_.context().registry.catalogue().AddObject(object);
    EXPECT_TRUE(added.ok()) << added.status().ToString();
    return added.ok() ? added->first.object_id : "";
  }

  ScenePickRequest Request() const {
    ScenePickRequest request;
    request.mount_id = mount_;
    grasping::SuctionCup cup;
    cup.diameter_m = 0.012;
    request.gripper = cup;
    request.grasp_options.max_grasps = 200;
    request.body_length_m = 0.08;
    return request;
  }

  testing::ServiceWorld world_;
  std::string scene_, block_mesh_, mount_;
};

TEST_F(ScenePicksTest, ABlockWithinReachIsPickedFromAboveAndTheArmReachesTheGrasp) {
  const std::string id = AddBlock(At(0.45, 0.1, 0), "block#1");
  const auto picks = CheckScenePicks(world_.context(), Request());
  ASSERT_TRUE(picks.ok()) << picks.status().ToString();
  ASSERT_EQ(picks->parts.size(), 1u);
  const ObjectPick& pick = picks->parts[0];
  EXPECT_EQ(pick.object_id, id);
  ASSERT_TRUE(pick.verdict.pickable) << grasping::PickFailureName(pick.verdict.failure) << ": " << pick.verdict.detail;
  // The cup on the top face, pointing down.
  EXPECT_NEAR(pick.verdict.world_from_tool.translation().z(), 0.02, 1e-6);
  EXPECT_NEAR(pick.verdict.world_from_tool.linear().col(2).z(), -1, 1e-6);
  // The joints put the mount's tool there (forward kinematics, independent of the solver).
  const auto mounted = world_.context().robots.Mount(mount_);
  ASSERT_TRUE(mounted.ok());
  const auto base_from_tool = robot::ForwardKinematics(*mounted->chain, pick.verdict.joint_positions);
  ASSERT_TRUE(base_from_tool.ok());
  const Pose3 world_from_tool = mounted->placement.frame_from_base * *base_from_tool;
  EXPECT_LT((world_from_tool.translation() - pick.verdict.world_from_tool.translation()).norm(), 1e-4);
  EXPECT_GT(world_from_tool.linear().col(2).dot(pick.verdict.world_from_tool.linear().col(2)), 0.9999);
  EXPECT_GT(picks->grasps_generated, 0u);
}

TEST_F(ScenePicksTest, ABlockBeyondTheArmsReachIsUnreachableAndOneUnderAnotherIsCovered) {
  const std::string far = AddBlock(At(2.5, 0, 0), "block#1");
  const std::string under = AddBlock(At(0.4, -0.1, 0), "block#2");
  const std::string over = AddBlock(At(0.41, -0.1, 0.0202), "block#3");
  const auto picks = CheckScenePicks(world_.context(), Request());
  ASSERT_TRUE(picks.ok()) << picks.status().ToString();
  ASSERT_EQ(picks->parts.size(), 3u);
  EXPECT_EQ(picks->parts[0].object_id, far);
  EXPECT_EQ(picks->parts[0].verdict.failure, grasping::PickFailure::kUnreachable) << picks->parts[0].verdict.detail;
  EXPECT_EQ(picks->parts[1].verdict.failure, grasping::PickFailure::kCovered);
  EXPECT_EQ(picks->parts[1].covered_by_object_id, over);
  EXPECT_TRUE(picks->parts[2].verdict.pickable) << picks->parts[2].verdict.detail;
  // Named parts only: the far block alone.
  ScenePickRequest request = Request();
  request.part_object_ids = {far};
  const auto one = CheckScenePicks(world_.context(), request);
  ASSERT_TRUE(one.ok());
  ASSERT_EQ(one->parts.size(), 1u);
  EXPECT_EQ(one->parts[0].object_id, far);
  // The lower block alone: the one on it is not among the parts asked about, and still covers it.
  request.part_object_ids = {under};
  const auto alone = CheckScenePicks(world_.context(), request);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(alone->parts[0].verdict.failure, grasping::PickFailure::kCovered);
  EXPECT_EQ(alone->parts[0].covered_by_object_id, over);
  EXPECT_EQ(alone->parts[0].verdict.detail, "object '" + over + "' (block#3) lies on it");
}

TEST_F(ScenePicksTest, BadRequestsAreRefusedNamingTheField) {
  AddBlock(At(0.45, 0.1, 0), "block#1");
  ScenePickRequest request = Request();
  request.mount_id = "mnt_nothere";
  EXPECT_EQ(CheckScenePicks(world_.context(), request).status().code(), StatusCode::kNotFound);
  request = Request();
  request.part_object_ids = {"obj_nothere"};
  auto refused = CheckScenePicks(world_.context(), request);
  EXPECT_EQ(refused.status().code(), StatusCode::kNotFound);
  EXPECT_NE(refused.status().message().find("part_object_ids[0]"), std::string::npos);
  request.part_object_ids = {"a", "a"};
  EXPECT_NE(CheckScenePicks(world_.context(), request).status().message().find("part_object_ids[1]"), std::string::npos);
  request = Request();
  request.body_length_m = 1e19;
  EXPECT_NE(CheckScenePicks(world_.context(), request).status().message().find("body_length_m"), std::string::npos);
  request = Request();
  request.ik_time_budget = std::chrono::microseconds(0);
  EXPECT_NE(CheckScenePicks(world_.context(), request).status().message().find("ik_time_budget_ms"), std::string::npos);
  // 1000 reach checks of 1 s solves: beyond the call's bound on inverse kinematics.
  request = Request();
  request.pick_options.max_reach_checks = 1000;
  request.ik_time_budget = std::chrono::seconds(1);
  const auto bounded = CheckScenePicks(world_.context(), request);
  EXPECT_EQ(bounded.status().code(), StatusCode::kResourceExhausted);
  EXPECT_NE(bounded.status().message().find("pick_options.max_reach_checks"), std::string::npos);
  request = Request();
  request.gripper = grasping::SuctionCup{std::nan(""), 0.01, 10, 0.9};
  EXPECT_EQ(CheckScenePicks(world_.context(), request).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(ScenePicksTest, ASceneWithoutBinPartsNeedsThePartsNamed) {
  AddBlock(At(0.45, 0.1, 0), "block");
  const auto picks = CheckScenePicks(world_.context(), Request());
  EXPECT_EQ(picks.status().code(), StatusCode::kFailedPrecondition);
}

}  // namespace
}  // namespace vscan::service
