// Campaign steps and a whole campaign through the service layer: a UR5 beside a rotary table
// looks at a floor square from a reachable viewpoint and tries one beyond its reach.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "api/reports/proto_report_writer.h"
#include "jobs/job_runner.h"
#include "service/campaign/campaign_run.h"
#include "service/campaign/campaign_step.h"
#include "service/campaign/campaign_summary.h"
#include "service_world.h"

namespace vscan::service {
namespace {

const Eigen::Vector3d kTarget(0.0, 0.0, 0.11);
const Eigen::Vector3d kReachable(0.25, 0.0, 0.30);
const Eigen::Vector3d kFarAway(-1.5, 0.0, 0.30);  // some 2 m from the base, beyond a UR5's reach

CampaignViewpoint Viewpoint(const Eigen::Vector3d& position) {
  CampaignViewpoint viewpoint;
  viewpoint.position = position;
  viewpoint.target = kTarget;
  viewpoint.goal = robot::LookAtGoal(position, kTarget, "viewpoint").value();
  return viewpoint;
}

class CampaignTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = world_.SceneWith(testing::FloorSquare(0.3), Pose3::Identity(), /*table=*/true);
    Pose3 base = Pose3::Identity();
    base.linear() = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    base.translation() = Eigen::Vector3d(0.55, 0.0, 0.0);
    plan_.scene_id = scene_;
    plan_.mount_id = world_.Mount("ur5", scene_, base);
    plan_.name = "square";
    plan_.seed = 7;
    plan_.scan.camera = sensor::CameraFromFov(48, 32, 60.0, 0.05, 3.0);
    plan_.scan.fields = kFieldPosition;
    plan_.scan.measurement.fields = kFieldPosition;
  }

  robot_registry::MountedRobot Mounted() { return world_.context().robots.Mount(plan_.mount_id).value(); }

  testing::ServiceWorld world_;
  std::string scene_;
  CampaignPlan plan_;
};

TEST_F(CampaignTest, AReachableStepScansFromWhereTheArmHoldsTheSensor) {
  const ViewpointSolution solution = SolveViewpoint(Mounted(), Viewpoint(kReachable)).value();
  ASSERT_TRUE(solution.reached);
  const auto step = RunStep(world_.context(), plan_, solution, 30.0, StepSeed(plan_.seed, 0), nullptr);
  ASSERT_TRUE(step.ok()) << step.status().ToString();
  ASSERT_EQ(step->outcome, StepResult::Outcome::kCaptured);
  EXPECT_LT((step->arm.achieved_pose.translation() - kReachable).norm(), 1e-4);
  const Eigen::Vector3d view = step->arm.achieved_pose.linear().col(2);
  EXPECT_GT(view.dot((kTarget - kReachable).normalized()), 1 - 1e-6);
  // Only the square is there to see (the arm's links are not visible): every point lies on it,
  // turned with the table by 30 degrees.
  ASSERT_GT(step->cloud.size(), 100u);
  const Eigen::Matrix3f table_from_world =
      Eigen::AngleAxisf(static_cast<float>(-30.0 * std::numbers::pi / 180.0), Eigen::Vector3f::UnitZ())
          .toRotationMatrix();
  for (const Eigen::Vector3f& p : step->cloud.positions) {
    const Eigen::Vector3f on_table = table_from_world * p;
    ASSERT_NEAR(on_table.z(), 0.0f, 1e-5f);
    ASSERT_LE(std::max(std::abs(on_table.x()), std::abs(on_table.y())), 0.3f + 1e-4f);
  }
}

TEST_F(CampaignTest, AViewpointBeyondReachIsAnUnreachableStep) {
  const ViewpointSolution solution = SolveViewpoint(Mounted(), Viewpoint(kFarAway)).value();
  EXPECT_FALSE(solution.reached);
  EXPECT_GT(solution.miss_distance, 0.5);
  const auto step = RunStep(world_.context(), plan_, solution, 0.0, 1, nullptr);
  ASSERT_TRUE(step.ok()) << step.status().ToString();
  EXPECT_EQ(step->outcome, StepResult::Outcome::kUnreachable);
  EXPECT_EQ(step->cloud.size(), 0u);
}

// What a campaign reports, kept for the test to read.
class RecordedJob final : public JobRecorder {
 public:
  Status Record(const JobEventUpdate& update) override {
    messages.push_back(update.message);
    return Status::Ok();
  }
  StatusOr<std::string> RecordArtifact(const std::string& name, const std::string&, const std::string& bytes,
                                       const ScanArtifact* scan, const store::CloudRecord* cloud,
                                       const JobEventUpdate& update) override {
    messages.push_back(update.message);
    artifacts.push_back(name);
    if (scan) scan_points.push_back(scan->points);
    if (cloud) clouds.push_back(*cloud);
    if (name == "campaign.json") summary = bytes;
    return "art_" + std::to_string(artifacts.size());
  }
  Status End(const JobEventUpdate& update) override {
    end_state = update.state;
    end_message = update.message;
    return Status::Ok();
  }
  const ReportWriter& reports() const override { return reports_; }

  api::ProtoReportWriter reports_;
  std::vector<std::string> messages;
  std::vector<std::string> artifacts;
  std::vector<uint64_t> scan_points;
  std::vector<store::CloudRecord> clouds;
  std::string summary;
  store::JobState end_state = store::JobState::kRunning;
  std::string end_message;
};

TEST_F(CampaignTest, ACampaignRecordsEveryStepThenItsSummary) {
  plan_.viewpoints = {Viewpoint(kReachable), Viewpoint(kFarAway)};
  plan_.rotations = 2;
  plan_.rotation_step_deg = 90.0;
  ASSERT_TRUE(CheckCampaignWorld(world_.context(), plan_, false).ok());
  RecordedJob job;
  jobs::JobControl control;
  RunCampaign(world_.context(), job, "job_test", plan_, control);

  EXPECT_EQ(job.end_state, store::JobState::kSucceeded) << job.end_message;
  EXPECT_EQ(job.end_message, "campaign done: 2 scans captured, 2 steps skipped");
  const std::vector<std::string> expected = {ScanArtifactName(0, 0), ScanArtifactName(1, 0), "campaign.json"};
  EXPECT_EQ(job.artifacts, expected);
  ASSERT_EQ(job.scan_points.size(), 2u);
  for (uint64_t points : job.scan_points) EXPECT_GT(points, 100u);
  int unreachable = 0;
  for (const std::string& message : job.messages) unreachable += message.find("unreachable") != std::string::npos;
  EXPECT_EQ(unreachable, 2);
  EXPECT_NE(job.summary.find("\"outcome\":\"unreachable\""), std::string::npos) << job.summary;

  // Each captured scan is also a cloud: where the arm put the sensor, the plan's camera, the angle.
  ASSERT_EQ(job.clouds.size(), 2u);
  for (size_t i = 0; i < job.clouds.size(); ++i) {
    const store::CloudRecord& cloud = job.clouds[i];
    EXPECT_EQ(cloud.name, ScanArtifactName(static_cast<uint32_t>(i), 0));
    EXPECT_EQ(cloud.points, job.scan_points[i]);
    EXPECT_EQ(cloud.fields, kFieldPosition);
    EXPECT_EQ(cloud.scene_id, scene_);
    EXPECT_EQ(cloud.frame, store::CloudFrame::kWorld);
    EXPECT_EQ(cloud.table_angle_deg, 90.0 * static_cast<double>(i));
    ASSERT_TRUE(cloud.world_from_sensor.has_value());
    EXPECT_LT((cloud.world_from_sensor->block<3, 1>(0, 3) - kReachable).norm(), 1e-4);
    ASSERT_TRUE(cloud.camera.has_value());
    EXPECT_EQ(cloud.camera->width, 48u);
    EXPECT_EQ(cloud.camera->far, 3.0);
  }
}

TEST_F(CampaignTest, AStoppedCampaignEndsCancelledAfterTheStepsItRan) {
  plan_.viewpoints = {Viewpoint(kReachable)};
  plan_.rotations = 3;
  plan_.rotation_step_deg = 120.0;
  RecordedJob job;
  jobs::JobControl control;
  control.RequestStop(jobs::StopReason::kCancelled);
  RunCampaign(world_.context(), job, "job_test", plan_, control);
  EXPECT_EQ(job.end_state, store::JobState::kCancelled);
  EXPECT_EQ(job.end_message, "cancelled after 0 of 3 steps");
  EXPECT_EQ(job.artifacts, std::vector<std::string>{"campaign.json"});
}

TEST_F(CampaignTest, TheWorldCheckNamesWhatIsMissing) {
  plan_.viewpoints = {Viewpoint(kReachable)};
  CampaignPlan other_scene = plan_;
  other_scene.scene_id = world_.SceneWith(testing::FloorSquare(0.3), Pose3::Identity());
  const Status wrong_scene = CheckCampaignWorld(world_.context(), other_scene, false);
  EXPECT_EQ(wrong_scene.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(wrong_scene.field(), "mount_id");

  other_scene.rotations = 2;  // that scene has no table to turn
  EXPECT_EQ(CheckCampaignWorld(world_.context(), other_scene, false).field(), "rotations");

  CampaignPlan no_mount = plan_;
  no_mount.mount_id.clear();
  EXPECT_TRUE(CheckCampaignWorld(world_.context(), no_mount, /*dry_run=*/true).ok());
  EXPECT_EQ(CheckCampaignWorld(world_.context(), no_mount, false).field(), "mount_id");
}

}  // namespace
}  // namespace vscan::service
