// A dataset plan's picks: the section's fields read and refused by name, and whole datasets of a
// block in a bin written with a UR5 beside the bin (pickable from above) or 3 m away (nothing
// reached), the same files on a second run.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "robot_registry/robot_registry.h"
#include "service/datasets/dataset_job_frames.h"
#include "service/datasets/dataset_job_setup.h"
#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "service/datasets/format/dataset_run.h"
#include "service_world.h"
#include "vscan_test/meshes.h"
#include "vscan_test/temp_dir.h"

namespace vscan::service {
namespace {

// One 40 x 30 x 20 mm block dropped into a 30 x 20 x 15 cm bin, seen by a small ideal camera.
std::string Plan(const std::string& picks) {
  return "name: picks\nbins:\n  - name: box\n    bin: {inner_size: [0.30, 0.20, 0.15]}\n"
         "    parts:\n      - {mesh: block.stl, unit: m, count: 1}\n"
         "seeds: [1, 2]\nsensors:\n  - {name: cam, preset: ideal-vga, width: 80, height: 60}\n"
         "camera_height_m: 0.6\n" +
         picks;
}

// A UR5 on a 0.2 m pedestal at x, facing the bin; a 12 mm cup 80 mm beyond the flange.
std::string PicksAt(double x) {
  return "picks:\n  robot_id: ROBOT\n  base: {xyz: [" + std::to_string(x) +
         ", 0, 0.2], rpy_deg: [0, 0, 0]}\n  gripper: {suction: {diameter: 0.012}}\n"
         "  grasp_options: {max_grasps: 200}\n  pick_options: {body_length: 0.08}\n";
}

StatusOr<dataset::DatasetPlan> Parse(const std::string& yaml) { return dataset::ParseDatasetPlanYaml(yaml, "plan"); }

// The message of a plan refused, or "" when it is read.
std::string Refusal(const std::string& picks) {
  const auto plan = Parse(Plan(picks));
  return plan.ok() ? "" : plan.status().message();
}

TEST(DatasetPicksPlan, ReadsEveryKey) {
  const auto plan = Parse(Plan(
      "picks:\n  robot_id: rob_1\n  base: {xyz: [0.5, -0.1, 0.2], rpy_deg: [0, 0, 90]}\n"
      "  tool: {xyz: [0, 0, 0.05]}\n  gripper: {jaws: {min_opening: 0.01, max_opening: 0.04, finger_width: 0.008}}\n"
      "  grasp_options: {max_grasps: 50, seed: 7, candidates: 300, surface_samples: 5000}\n"
      "  pick_options: {approach_distance: 0.03, max_approach_tilt_deg: 30, cover_distance: 0.004,\n"
      "                 max_reach_checks: 4, body_length: 0.09, ik_iterations: 500}\n"));
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  ASSERT_TRUE(plan->picks.has_value());
  const dataset::DatasetPicks& picks = *plan->picks;
  EXPECT_EQ(picks.robot_id, "rob_1");
  EXPECT_TRUE(picks.world_from_base.translation().isApprox(Eigen::Vector3d(0.5, -0.1, 0.2)));
  EXPECT_TRUE(picks.world_from_base.linear().col(0).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  ASSERT_TRUE(picks.flange_from_tool.has_value());
  EXPECT_DOUBLE_EQ(picks.flange_from_tool->translation().z(), 0.05);
  const auto& jaws = std::get<grasping::ParallelJaws>(picks.gripper);
  EXPECT_DOUBLE_EQ(jaws.max_opening_m, 0.04);
  EXPECT_DOUBLE_EQ(jaws.finger_width_m, 0.008);
  EXPECT_EQ(picks.grasp_options.max_grasps, 50u);
  EXPECT_EQ(picks.grasp_options.seed, 7u);
  EXPECT_EQ(picks.grasp_options.candidates, 300u);
  EXPECT_EQ(picks.pick_options.seed, 7u);
  EXPECT_DOUBLE_EQ(picks.pick_options.sweep.approach_m, 0.03);
  EXPECT_DOUBLE_EQ(picks.pick_options.cover_distance_m, 0.004);
  EXPECT_EQ(picks.pick_options.max_reach_checks, 4u);
  EXPECT_DOUBLE_EQ(picks.pick_options.sweep.body_length_m, 0.09);
  EXPECT_EQ(picks.ik_iterations, 500u);
  // Without picks, no section.
  EXPECT_FALSE(Parse(Plan(""))->picks.has_value());
}

TEST(DatasetPicksPlan, RefusesABadFieldNamingIt) {
  const std::string base = "  base: {xyz: [0.5, 0, 0.2]}\n";
  const std::string cup = "  gripper: {suction: {diameter: 0.012}}\n";
  const std::pair<std::string, std::string> cases[] = {
      {"picks:\n" + base + cup, "picks.robot_id: required"},
      {"picks:\n  robot_id: r\n" + cup, "picks.base: required"},
      {"picks:\n  robot_id: r\n" + base, "picks.gripper: required"},
      {"picks:\n  robot_id: r\n  base: {xyz: [.nan, 0, 0.2]}\n" + cup, "picks.base.xyz"},
      {"picks:\n  robot_id: r\n  base: {xyz: [1e19, 0, 0.2]}\n" + cup, "picks.base.xyz: must be within 1000 m"},
      {"picks:\n  robot_id: r\n  base: {xyz: [0, 0, 0], quat: [2, 0, 0, 0]}\n" + cup, "picks.base.quat"},
      {"picks:\n  robot_id: r\n" + base + "  gripper: {suction: {diameter: 0}}\n", "picks.gripper.suction.diameter: "},
      {"picks:\n  robot_id: r\n" + base + "  gripper: {suction: {diameter: .nan}}\n", "picks.gripper.suction.diameter"},
      {"picks:\n  robot_id: r\n" + base + "  gripper: {suction: {diameter: 0.01}, jaws: {}}\n", "picks.gripper: give exactly one"},
      {"picks:\n  robot_id: r\n" + base + "  gripper: {jaws: {min_opening: 0.05, max_opening: 0.01}}\n",
       "picks.gripper.jaws.max_opening: must be >= "},
      {"picks:\n  robot_id: r\n" + base + cup + "  grasp_options: {max_grasps: 100000000000}\n",
       "picks.grasp_options.max_grasps: must be in [1, 100000]"},
      {"picks:\n  robot_id: r\n" + base + cup + "  pick_options: {max_reach_checks: 0}\n",
       "picks.pick_options.max_reach_checks: must be in [1, 1000]"},
      {"picks:\n  robot_id: r\n" + base + cup + "  pick_options: {body_length: 1e19}\n",
       "picks.pick_options.body_length: must be in [0, 10] m"},
      {"picks:\n  robot_id: r\n" + base + cup + "  pick_options: {ik_iterations: 1000000000}\n",
       "picks.pick_options.ik_iterations"},
      {"picks:\n  robot_id: r\n" + base + cup + "  pick_options: {speed: 3}\n", "picks.pick_options.speed: unknown key"},
      {"picks:\n  robot_id: r\n  urdf: ur5.urdf\n" + base + cup, "picks.urdf: unknown key"},
  };
  for (const auto& [picks, expected] : cases) {
    const std::string message = Refusal(picks);
    EXPECT_NE(message.find(expected), std::string::npos) << picks << " -> " << message;
    EXPECT_EQ(message.rfind("plan:", 0), 0u) << message;  // the file and the line
  }
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

class DatasetPicksRun : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string mount = world_.Mount("ur5", world_.EmptyScene(), Pose3::Identity());
    auto mounted = world_.context().robots.Mount(mount);
    ASSERT_TRUE(mounted.ok()) << mounted.status().ToString();
    robot_id_ = mounted->mount.robot_id;
  }

  // The plan's setup with the picks' robot resolved, as a dataset job prepares it.
  StatusOr<std::shared_ptr<const DatasetSetup>> Setup(const std::string& picks) {
    std::string yaml = Plan(picks);
    if (const size_t at = yaml.find("ROBOT"); at != std::string::npos) yaml.replace(at, 5, robot_id_);
    ASSIGN_OR_RETURN(plan_, Parse(yaml));
    const DatasetMeshLoader load = [](const dataset::DatasetPart&, const std::string&) -> StatusOr<TriangleMesh> {
      return test::MakeBox({-0.02, -0.015, -0.01}, {0.02, 0.015, 0.01});
    };
    ASSIGN_OR_RETURN(DatasetSetup setup, PrepareDataset(plan_, load, 1u << 22));
    ASSIGN_OR_RETURN(auto chain, world_.context().robots.Chain(robot_id_));
    RETURN_IF_ERROR(AddDatasetPicks(setup, chain));
    return std::make_shared<const DatasetSetup>(std::move(setup));
  }

  // The whole plan written into root.
  Status Write(const std::filesystem::path& root, const std::string& picks) {
    ASSIGN_OR_RETURN(auto setup, Setup(picks));
    return dataset::WriteDataset(root, plan_, setup->parts, BinFrameSource(setup, nullptr), {}).status();
  }

  testing::ServiceWorld world_;
  std::string robot_id_;
  dataset::DatasetPlan plan_;
  test::TempDir dir_;
};

TEST_F(DatasetPicksRun, ABlockAloneInTheBinIsPickedFromAboveAndTheFileSaysSo) {
  auto setup = Setup(PicksAt(-0.45));
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  ASSERT_TRUE((*setup)->picks);
  EXPECT_FALSE((*setup)->picks->grasps[0].empty());
  const auto frame = BinFrameSource(*setup, nullptr)(dataset::SceneAt(plan_, 0), 0);
  ASSERT_TRUE(frame.ok()) << frame.status().ToString();
  ASSERT_TRUE(frame->picks);
  ASSERT_EQ(frame->picks->size(), 1u);
  const dataset::PartPickRecord& pick = frame->picks->front();
  ASSERT_TRUE(pick.pickable) << pick.failure << ": " << pick.detail;
  EXPECT_EQ(pick.failure, "PICK_FAILURE_UNSPECIFIED");
  ASSERT_TRUE(pick.grasp.has_value());
  // The tool's z (the approach) points down onto the block, the cup on its top.
  EXPECT_LT(pick.world_from_tool.linear().col(2).z(), -0.9);
  const Pose3& part = frame->objects.at(0).world_from_object;
  EXPECT_LT((pick.world_from_tool.translation().head<2>() - part.translation().head<2>()).norm(), 0.03);
  EXPECT_GT(pick.world_from_tool.translation().z(), part.translation().z());

  const std::filesystem::path root = dir_.path() / "near";
  ASSERT_TRUE(Write(root, PicksAt(-0.45)).ok());
  const std::string json = ReadFile(dataset::SceneDir(root, 0) / dataset::kScenePickableFile);
  EXPECT_NE(json.find("\"pickable\":true"), std::string::npos) << json;
  EXPECT_NE(json.find("\"world_R_tool\""), std::string::npos) << json;
  EXPECT_NE(ReadFile(root / dataset::kManifestFile).find("\"robot_id\""), std::string::npos);
}

TEST_F(DatasetPicksRun, ARobotThreeMetresAwayReachesNothing) {
  const std::filesystem::path root = dir_.path() / "far";
  ASSERT_TRUE(Write(root, PicksAt(-3.0)).ok());
  for (const uint64_t scene : {0, 1}) {
    const std::string json = ReadFile(dataset::SceneDir(root, scene) / dataset::kScenePickableFile);
    EXPECT_EQ(json.find("\"pickable\":true"), std::string::npos) << json;
    EXPECT_NE(json.find("PICK_FAILURE_UNREACHABLE"), std::string::npos) << json;
    EXPECT_NE(json.find("\"grasp\":null"), std::string::npos) << json;
  }
}

TEST_F(DatasetPicksRun, TwoRunsWriteTheSameFilesAndAPlanWithoutPicksWritesNone) {
  const std::filesystem::path first = dir_.path() / "first", second = dir_.path() / "second";
  ASSERT_TRUE(Write(first, PicksAt(-0.45)).ok());
  ASSERT_TRUE(Write(second, PicksAt(-0.45)).ok());
  for (const uint64_t scene : {0, 1}) {
    for (const char* file : {dataset::kScenePickableFile, dataset::kSceneRecordFile}) {
      const std::string a = ReadFile(dataset::SceneDir(first, scene) / file);
      EXPECT_FALSE(a.empty()) << file;
      EXPECT_EQ(a, ReadFile(dataset::SceneDir(second, scene) / file)) << file;
    }
  }
  const std::filesystem::path none = dir_.path() / "none";
  ASSERT_TRUE(Write(none, "").ok());
  EXPECT_FALSE(std::filesystem::exists(dataset::SceneDir(none, 0) / dataset::kScenePickableFile));
  EXPECT_EQ(ReadFile(none / dataset::kManifestFile).find("\"robot_id\""), std::string::npos);
}

TEST_F(DatasetPicksRun, TooMuchInverseKinematicsIsRefusedNamingTheField) {
  std::string heavy = PicksAt(-0.45);
  heavy.replace(heavy.find("{body_length: 0.08}"), 19, "{body_length: 0.08, max_reach_checks: 1000, ik_iterations: 100000}");
  const auto refused = Setup(heavy);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.status().field(), "picks.pick_options.max_reach_checks") << refused.status().ToString();
}

}  // namespace
}  // namespace vscan::service
