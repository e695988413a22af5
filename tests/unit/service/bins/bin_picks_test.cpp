// A bin fill that asks for picks: a few blocks in the box bin beside a UR5 with a suction cup.
// bin.json carries one verdict per placed part; a pickable part's tool lies on the part's true
// surface with an approach from above; a mount out of reach picks nothing; a bad picks section is
// refused before any physics, naming its field.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "api/bins/bin_fill_spec.h"
#include "api/bins/bin_picks_spec.h"
#include "service/picking/scene_picks.h"
#include "api/reports/proto_report_writer.h"
#include "jobs/job_runner.h"
#include "service/bins/bin_fill_run.h"
#include "recorded_fill.h"
#include "service_world.h"
#include "vscan/common/proto_convert.h"
#include "vscan/common/report_json.h"
#include "vscan/v1/reports.pb.h"
#include "vscan_test/meshes.h"

// Its own namespace: the layer's tests share one unity build.
namespace vscan::service::bin_picks {
namespace {

const Eigen::Vector3d kBlockLo(-0.02, -0.015, 0), kBlockHi(0.02, 0.015, 0.02);

Pose3 At(double x, double y, double z) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

using testing::RecordedFill;

// The distance from p (part frame) to the block's surface, from inside or outside.
double DistanceToBlockSurface(const Eigen::Vector3d& p) {
  const Eigen::Vector3d outside = (kBlockLo - p).cwiseMax(p - kBlockHi).cwiseMax(0.0);
  if (outside.norm() > 0) return outside.norm();
  return (p - kBlockLo).cwiseMin(kBlockHi - p).minCoeff();
}

Pose3 PoseOf(const google::protobuf::RepeatedField<double>& m) {
  Eigen::Matrix4d matrix;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) matrix(r, c) = m.Get(r * 4 + c);
  }
  return Pose3(matrix);
}

// A scene with a floor and a UR5 on a 0.2 m pedestal at base; five blocks fill a 16 x 12 x 8 cm
// box bin at (0.45, 0, 0).
class BinPicksTest : public ::testing::Test {
 protected:
  void SetUp() override { block_mesh_ = world_.AddMesh(test::MakeBox(kBlockLo, kBlockHi), "block"); }

  std::string SceneWithMount(const Pose3& world_from_base, std::string* mount) {
    const std::string scene = world_.SceneWith(testing::FloorSquare(1.0), Pose3::Identity());
    *mount = world_.Mount("ur5", scene, world_from_base);
    return scene;
  }

  v1::BinFillSpec Spec(const std::string& scene, const std::string& mount) const {
    v1::BinFillSpec spec;
    spec.set_scene_id(scene);
    spec.set_seed(5);
    spec.set_name("bin");
    *spec.mutable_bin()->mutable_inner_size() = ToProto(Eigen::Vector3d(0.16, 0.12, 0.08));
    *spec.mutable_bin()->mutable_pose() = PoseToProto(At(0.45, 0, 0));
    v1::BinPart* part = spec.add_parts();
    part->set_mesh_id(block_mesh_);
    part->set_count(5);
    part->set_name("block");
    spec.mutable_physics()->set_max_simulated_s(20);
    v1::BinPicks* picks = spec.mutable_picks();
    picks->set_mount_id(mount);
    picks->mutable_gripper()->mutable_suction()->set_diameter(0.012);
    picks->mutable_grasp_options()->set_max_grasps(200);
    picks->mutable_pick_options()->set_body_length(0.08);
    return spec;
  }

  // The fill run as the job runs it; bin.json read back through its schema.
  v1::BinReport Fill(const v1::BinFillSpec& spec, RecordedFill& recorder) {
    auto plan = api::ValidateBinFill(spec, world_.context(), false);
    EXPECT_TRUE(plan.ok()) << plan.status().ToString();
    if (!plan.ok()) return {};
    RunBinFill(world_.context().registry, recorder, "job_test", *plan, recorder.control);
    v1::BinReport report;
    const Status parsed = ParseReport(recorder.bin_json, "bin.json", &report);
    EXPECT_TRUE(parsed.ok()) << parsed.ToString();
    return report;
  }

  testing::ServiceWorld world_;
  std::string block_mesh_;
};

TEST_F(BinPicksTest, EveryPartGetsAVerdictAndAPickablePartsToolLiesOnItsSurfaceFromAbove) {
  std::string mount;
  const std::string scene = SceneWithMount(At(0, 0, 0.2), &mount);
  RecordedFill recorder;
  const v1::BinReport report = Fill(Spec(scene, mount), recorder);
  ASSERT_EQ(recorder.end_state, store::JobState::kSucceeded) << recorder.end_message;
  ASSERT_TRUE(report.applied());
  ASSERT_TRUE(report.has_picks());
  ASSERT_GE(report.parts_size(), 3);
  EXPECT_EQ(report.picks().parts_checked(), static_cast<uint32_t>(report.parts_size()));
  EXPECT_EQ(report.picks().mount_id(), mount);
  EXPECT_EQ(report.picks().gripper(), "suction");

  // The parts' true poses from the scene, not from the report.
  const auto stored = world_.context().registry.catalogue().GetScene(scene);
  ASSERT_TRUE(stored.ok());
  std::map<std::string, Pose3> world_from_object;
  for (const store::ObjectRecord& object : stored->objects) world_from_object[object.object_id] = Pose3(object.pose);

  uint32_t pickable = 0;
  for (const v1::BinReportPart& part : report.parts()) {
    ASSERT_TRUE(part.has_pick()) << part.label();
    const v1::BinReportPick& pick = part.pick();
    if (!pick.pickable()) {
      EXPECT_NE(pick.failure(), "none") << part.label();
      EXPECT_TRUE(pick.world_from_tool().empty());
      continue;
    }
    ++pickable;
    EXPECT_EQ(pick.failure(), "none");
    ASSERT_EQ(pick.world_from_tool_size(), 16);
    ASSERT_EQ(pick.part_from_tool_size(), 16);
    ASSERT_EQ(pick.approach_size(), 3);
    EXPECT_EQ(pick.joint_positions_size(), 6);
    const Pose3 world_from_tool = PoseOf(pick.world_from_tool());
    const Pose3 world_from_part = world_from_object.at(part.object_id());
    const Eigen::Vector3d tool_in_part = world_from_part.inverse() * world_from_tool.translation();
    EXPECT_LT(DistanceToBlockSurface(tool_in_part), 1e-3) << part.label();
    const double down = world_from_tool.linear().col(2).dot(-Eigen::Vector3d::UnitZ());
    EXPECT_GE(down, std::cos(60 * M_PI / 180) - 1e-9) << part.label();
    // The grasp in the part frame is the same tool seen from the part.
    EXPECT_LT(((world_from_part * PoseOf(pick.part_from_tool())).matrix() - world_from_tool.matrix()).cwiseAbs().maxCoeff(), 1e-9)
        << (world_from_part * PoseOf(pick.part_from_tool())).matrix() << "\n" << world_from_tool.matrix();
    const Eigen::Vector3d approach(pick.approach(0), pick.approach(1), pick.approach(2));
    EXPECT_TRUE(approach.isApprox(world_from_part.linear().inverse() * world_from_tool.linear().col(2), 1e-9));
  }
  EXPECT_GT(pickable, 0u);
  EXPECT_EQ(report.picks().pickable(), pickable);
  EXPECT_NE(recorder.end_message.find(std::to_string(pickable) + " of " + std::to_string(report.parts_size()) +
                                      " parts pickable"),
            std::string::npos)
      << recorder.end_message;

  // The check is deterministic for the same scene: asked again, the same flags.
  auto asked = api::BinPicksFromProto(Spec(scene, mount).picks());
  ASSERT_TRUE(asked.ok()) << asked.status().ToString();
  ScenePickRequest again = *asked;
  for (const v1::BinReportPart& part : report.parts()) again.part_object_ids.push_back(part.object_id());
  const auto rechecked = CheckScenePicks(world_.context(), again);
  ASSERT_TRUE(rechecked.ok()) << rechecked.status().ToString();
  ASSERT_EQ(rechecked->parts.size(), static_cast<size_t>(report.parts_size()));
  for (int i = 0; i < report.parts_size(); ++i) {
    EXPECT_EQ(rechecked->parts[i].verdict.pickable, report.parts(i).pick().pickable()) << report.parts(i).label();
    EXPECT_EQ(grasping::PickFailureName(rechecked->parts[i].verdict.failure), report.parts(i).pick().failure());
  }
}

TEST_F(BinPicksTest, AMountThreeMetresAwayPicksNothing) {
  std::string near_mount, far_mount;
  const std::string near_scene = SceneWithMount(At(0, 0, 0.2), &near_mount);
  const std::string far_scene = SceneWithMount(At(-2.55, 0, 0.2), &far_mount);
  RecordedFill near_fill, far_fill;
  const v1::BinReport near = Fill(Spec(near_scene, near_mount), near_fill);
  const v1::BinReport far = Fill(Spec(far_scene, far_mount), far_fill);
  ASSERT_EQ(far_fill.end_state, store::JobState::kSucceeded) << far_fill.end_message;
  ASSERT_TRUE(far.has_picks());
  EXPECT_EQ(far.picks().pickable(), 0u);
  // The same seed settles the same pile: what the near arm could pick, the far one cannot reach.
  ASSERT_EQ(near.parts_size(), far.parts_size());
  int reachable_near = 0;
  for (int i = 0; i < far.parts_size(); ++i) {
    EXPECT_FALSE(far.parts(i).pick().pickable()) << far.parts(i).label();
    if (near.parts(i).pick().pickable()) {
      ++reachable_near;
      EXPECT_EQ(far.parts(i).pick().failure(), "unreachable") << far.parts(i).pick().detail();
    }
  }
  EXPECT_GT(reachable_near, 0);
}

TEST_F(BinPicksTest, ACancelDuringThePickCheckEndsTheJobCancelledWithThePartsPlaced) {
  std::string mount;
  const std::string scene = SceneWithMount(At(0, 0, 0.2), &mount);
  RecordedFill recorder;
  recorder.stop_when = "checking picks";
  const v1::BinReport report = Fill(Spec(scene, mount), recorder);
  EXPECT_EQ(recorder.end_state, store::JobState::kCancelled) << recorder.end_message;
  EXPECT_NE(recorder.end_message.find("the pick check did not finish"), std::string::npos) << recorder.end_message;
  EXPECT_TRUE(report.applied());
  EXPECT_FALSE(report.has_picks());
  for (const v1::BinReportPart& part : report.parts()) EXPECT_FALSE(part.has_pick());
  // The scene holds the bin and the parts.
  EXPECT_EQ(world_.context().registry.catalogue().GetScene(scene)->objects.size(), 2u + report.parts_size());
}

TEST_F(BinPicksTest, ABadPicksSectionIsRefusedNamingItsFieldBeforeAnyPhysics) {
  std::string mount, other_mount;
  const std::string scene = SceneWithMount(At(0, 0, 0.2), &mount);
  SceneWithMount(At(0, 0, 0.2), &other_mount);
  const uint64_t revision = world_.context().registry.catalogue().GetScene(scene)->revision;
  const auto refused = [&](const v1::BinFillSpec& spec) {
    return api::ValidateBinFill(spec, world_.context(), false).status();
  };

  v1::BinFillSpec spec = Spec(scene, "mnt_nothere");
  Status status = refused(spec);
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << status.ToString();
  EXPECT_TRUE(status.message().starts_with("spec.picks.mount_id:")) << status.ToString();

  status = refused(Spec(scene, other_mount));
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition) << status.ToString();
  EXPECT_TRUE(status.message().starts_with("spec.picks.mount_id:")) << status.ToString();

  spec = Spec(scene, "");
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.mount_id:")) << refused(spec).ToString();

  spec = Spec(scene, mount);
  spec.mutable_picks()->clear_gripper();
  status = refused(spec);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(status.message().starts_with("spec.picks.gripper:")) << status.ToString();

  for (const double bad : {std::nan(""), -0.01, 1e19}) {
    spec = Spec(scene, mount);
    spec.mutable_picks()->mutable_gripper()->mutable_suction()->set_diameter(bad);
    status = refused(spec);
    EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_TRUE(status.message().starts_with("spec.picks.gripper.suction.diameter")) << status.ToString();
  }
  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_gripper()->mutable_jaws()->set_min_opening(0.05);
  spec.mutable_picks()->mutable_gripper()->mutable_jaws()->set_max_opening(0.01);
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.gripper.jaws.")) << refused(spec).ToString();

  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_grasp_options()->set_max_grasps(4000000000u);
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.grasp_options.max_grasps:")) << refused(spec).ToString();
  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_grasp_options()->set_surface_samples(2000000);
  spec.mutable_picks()->mutable_grasp_options()->set_candidates(100000);
  status = refused(spec);
  EXPECT_EQ(status.code(), StatusCode::kResourceExhausted) << status.ToString();
  EXPECT_TRUE(status.message().starts_with("spec.picks.grasp_options.candidates:")) << status.ToString();

  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_pick_options()->set_approach_distance(std::nan(""));
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.pick_options.approach_distance:"));
  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_pick_options()->set_body_length(1e19);
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.pick_options.body_length:"));
  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_pick_options()->set_ik_time_budget_ms(5000);
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.pick_options.ik_time_budget_ms:"));
  spec = Spec(scene, mount);
  spec.mutable_picks()->mutable_pick_options()->set_max_reach_checks(5000);
  EXPECT_TRUE(refused(spec).message().starts_with("spec.picks.pick_options.max_reach_checks:"));

  // Checked only: the scene is as it was.
  EXPECT_EQ(world_.context().registry.catalogue().GetScene(scene)->revision, revision);
  // A good section passes.
  EXPECT_TRUE(refused(Spec(scene, mount)).ok()) << refused(Spec(scene, mount)).ToString();
}

}  // namespace
}  // namespace vscan::service::bin_picks
