#include "store/robot_catalogue.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "store/catalogue.h"
#include "vscan_test/temp_dir.h"

namespace vscan::store {
namespace {

RobotRecord SampleRobot(const std::string& sha256) {
  RobotRecord r;
  r.name = "arm";
  r.urdf_path = "robots/arm.urdf";
  r.base_link = "base";
  r.tip_link = "tool0";
  r.tool_offset(0, 3) = 0.05;
  r.bundle_sha256 = sha256;
  r.bundle_bytes = 1234;
  r.file_count = 3;
  r.joints = {{"j1", JointKind::kRevolute, -2.5, 2.5, 3.1},
              {"j2", JointKind::kContinuous, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 0.0},
              {"slide", JointKind::kPrismatic, 0.0, 0.2, 0.5}};
  r.reach = 0.85;
  r.warnings = {"links['a'].visual[0].mesh: missing", "second\nline"};
  return r;
}

std::string Sha(char c) { return std::string(64, c); }

class RobotCatalogueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto scenes = Catalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(scenes.ok()) << scenes.status().ToString();
    scenes_ = std::move(scenes).value();
    auto robots = RobotCatalogue::Open(dir_.path() / "catalogue.sqlite");
    ASSERT_TRUE(robots.ok()) << robots.status().ToString();
    robots_ = std::move(robots).value();
  }

  uint64_t Revision(const std::string& scene_id) { return scenes_->GetScene(scene_id)->revision; }

  test::TempDir dir_;
  std::unique_ptr<Catalogue> scenes_;
  std::unique_ptr<RobotCatalogue> robots_;
};

TEST_F(RobotCatalogueTest, RobotsRoundTrip) {
  auto inserted = robots_->InsertRobot(SampleRobot(Sha('a')));
  ASSERT_TRUE(inserted.ok()) << inserted.status().ToString();
  EXPECT_EQ(inserted->robot_id.rfind("rbt_", 0), 0u);
  auto got = robots_->GetRobot(inserted->robot_id);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->name, "arm");
  EXPECT_EQ(got->tool_offset, inserted->tool_offset);
  ASSERT_EQ(got->joints.size(), 3u);
  EXPECT_EQ(got->joints[1].name, "j2");
  EXPECT_TRUE(std::isinf(got->joints[1].upper));
  EXPECT_EQ(got->joints[2].type, JointKind::kPrismatic);
  EXPECT_EQ(got->warnings, inserted->warnings);
  EXPECT_EQ(got->create_time_ms, inserted->create_time_ms);
  EXPECT_EQ(robots_->GetRobot("rbt_missing").status().code(), StatusCode::kNotFound);
}

TEST_F(RobotCatalogueTest, ListsInIdOrderAndPages) {
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(robots_->InsertRobot(SampleRobot(Sha('b'))).ok());
  auto all = robots_->ListRobots("", 10);
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->size(), 5u);
  for (size_t i = 1; i < all->size(); ++i) EXPECT_LT((*all)[i - 1].robot_id, (*all)[i].robot_id);
  auto rest = robots_->ListRobots((*all)[1].robot_id, 10);
  ASSERT_TRUE(rest.ok());
  EXPECT_EQ(rest->size(), 3u);
  EXPECT_EQ(robots_->ListRobots("", 0).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(RobotCatalogueTest, MountsBumpRevisionsAndGuardDeletion) {
  auto scene = scenes_->CreateScene("cell");
  ASSERT_TRUE(scene.ok());
  auto a = robots_->InsertRobot(SampleRobot(Sha('c')));
  auto b = robots_->InsertRobot(SampleRobot(Sha('c')));
  ASSERT_TRUE(a.ok() && b.ok());

  MountRecord mount;
  mount.scene_id = scene->scene_id;
  mount.robot_id = a->robot_id;
  mount.base_pose(0, 3) = 0.4;
  mount.encoder_sigma = {0.01, 0.02, 0.001};
  auto added = robots_->InsertMount(mount);
  ASSERT_TRUE(added.ok()) << added.status().ToString();
  EXPECT_EQ(added->second, 2u);
  EXPECT_EQ(Revision(scene->scene_id), 2u);
  auto got = robots_->GetMount(added->first.mount_id);
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->base_pose, mount.base_pose);
  EXPECT_FALSE(got->tool_offset.has_value());
  EXPECT_EQ(got->encoder_sigma, mount.encoder_sigma);

  auto refused = robots_->DeleteRobot(a->robot_id);
  EXPECT_EQ(refused.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(refused.status().message().find(added->first.mount_id), std::string::npos);

  MountRecord bad = mount;
  bad.scene_id = "scn_missing";
  EXPECT_EQ(robots_->InsertMount(bad).status().code(), StatusCode::kNotFound);
  bad = mount;
  bad.robot_id = "rbt_missing";
  EXPECT_EQ(robots_->InsertMount(bad).status().code(), StatusCode::kNotFound);
  bad = mount;
  bad.encoder_sigma = {-1.0};
  EXPECT_EQ(robots_->InsertMount(bad).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(Revision(scene->scene_id), 2u);

  auto removed = robots_->DeleteMount(added->first.mount_id);
  ASSERT_TRUE(removed.ok());
  EXPECT_EQ(*removed, 3u);
  EXPECT_EQ(robots_->DeleteMount(added->first.mount_id).status().code(), StatusCode::kNotFound);

  auto deleted = robots_->DeleteRobot(a->robot_id);
  ASSERT_TRUE(deleted.ok());
  EXPECT_EQ(deleted->first, Sha('c'));
  EXPECT_FALSE(deleted->second);  // b shares the bundle
  deleted = robots_->DeleteRobot(b->robot_id);
  ASSERT_TRUE(deleted.ok());
  EXPECT_TRUE(deleted->second);
}

TEST_F(RobotCatalogueTest, DeletingASceneRemovesItsMounts) {
  auto scene = scenes_->CreateScene("gone");
  auto other = scenes_->CreateScene("kept");
  auto robot = robots_->InsertRobot(SampleRobot(Sha('d')));
  ASSERT_TRUE(scene.ok() && other.ok() && robot.ok());
  MountRecord mount;
  mount.robot_id = robot->robot_id;
  mount.scene_id = scene->scene_id;
  auto doomed = robots_->InsertMount(mount);
  mount.scene_id = other->scene_id;
  mount.tool_offset = Eigen::Matrix4d::Identity();
  auto kept = robots_->InsertMount(mount);
  ASSERT_TRUE(doomed.ok() && kept.ok());
  EXPECT_EQ(robots_->ListMounts(scene->scene_id, "", 10)->size(), 1u);
  EXPECT_EQ(robots_->ListMounts("", "", 10)->size(), 2u);

  ASSERT_TRUE(scenes_->DeleteScene(scene->scene_id).ok());
  EXPECT_EQ(robots_->GetMount(doomed->first.mount_id).status().code(), StatusCode::kNotFound);
  auto survivor = robots_->GetMount(kept->first.mount_id);
  ASSERT_TRUE(survivor.ok());
  EXPECT_TRUE(survivor->tool_offset.has_value());
  EXPECT_EQ(robots_->ListMounts(scene->scene_id, "", 10).status().code(), StatusCode::kNotFound);
}

TEST_F(RobotCatalogueTest, SurvivesReopening) {
  auto scene = scenes_->CreateScene("durable");
  auto robot = robots_->InsertRobot(SampleRobot(Sha('e')));
  ASSERT_TRUE(scene.ok() && robot.ok());
  MountRecord mount;
  mount.robot_id = robot->robot_id;
  mount.scene_id = scene->scene_id;
  auto added = robots_->InsertMount(mount);
  ASSERT_TRUE(added.ok());
  robots_.reset();
  auto reopened = RobotCatalogue::Open(dir_.path() / "catalogue.sqlite");
  ASSERT_TRUE(reopened.ok());
  EXPECT_TRUE((*reopened)->GetRobot(robot->robot_id).ok());
  EXPECT_TRUE((*reopened)->GetMount(added->first.mount_id).ok());
}

}  // namespace
}  // namespace vscan::store
