#include "model_test_world.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <numbers>

#include <gtest/gtest.h>

#include "geometry/mesh_import.h"
#include "jobs/job_runner.h"
#include "robot_fixtures.h"
#include "service/campaign/campaign_run.h"
#include "service/campaign/campaign_summary.h"
#include "service/model/model_run.h"

namespace vscan::service::testing {
namespace {

template <typename T>
T Must(StatusOr<T> value) {
  if (!value.ok()) ADD_FAILURE() << value.status().ToString();
  return std::move(value).value();
}

}  // namespace

StoredJob::StoredJob(ServiceWorld& world, const std::string& kind) : world_(world) {
  store::JobRecord record;
  record.kind = kind;
  record.message = "queued";
  job_id = Must(world.jobs().InsertJob(record)).job_id;
}

store::JobProgress StoredJob::Progress(const JobEventUpdate& update) {
  steps_done.push_back(update.steps_done);
  return {update.state, update.message, update.steps_done, ++sequence_, 0};
}

Status StoredJob::Record(const JobEventUpdate& update) {
  messages.push_back(update.message);
  if (update.alignment) alignments.push_back(*update.alignment);
  return world_.jobs().UpdateProgress(job_id, Progress(update));
}

StatusOr<std::string> StoredJob::RecordArtifact(const std::string& name, const std::string& media_type,
                                                const std::string& bytes, const ScanArtifact* scan,
                                                const store::CloudRecord* cloud, const JobEventUpdate& update) {
  messages.push_back(update.message);
  ASSIGN_OR_RETURN(const store::BlobPin pin, world_.blobs().PutPinned(bytes));
  store::ArtifactRecord artifact;
  artifact.job_id = job_id;
  artifact.name = name;
  artifact.media_type = media_type;
  artifact.sha256 = pin.sha256();
  artifact.size_bytes = bytes.size();
  std::optional<store::CloudRecord> row;
  if (cloud) row = *cloud;
  ASSIGN_OR_RETURN(const store::ArtifactRecord stored,
                   world_.jobs().AddArtifact(artifact, Progress(update), row ? &*row : nullptr));
  artifacts[name] = bytes;
  if (scan) scans.push_back({name, scan->commanded_sensor_pose, scan->commanded_joint_positions});
  return stored.artifact_id;
}

Status StoredJob::End(const JobEventUpdate& update) {
  end_state = update.state;
  end_message = update.message;
  return world_.jobs().UpdateProgress(job_id, Progress(update));
}

StatusOr<CampaignRecord> TestCampaignRecords::Get(const std::string& job_id) {
  ASSIGN_OR_RETURN(const store::JobRecord job, world_.jobs().GetJob(job_id));
  CampaignRecord record;
  if (const auto it = records_.find(job_id); it != records_.end()) record = it->second;
  record.job_id = job.job_id;
  record.kind = job.kind;
  record.state = job.state;
  return record;
}

ModelWorld::ModelWorld(double encoder_sigma, const TriangleMesh& object, const Pose3& world_from_object) {
  scene_id = world.SceneWith(object, world_from_object, /*table=*/true);
  Eigen::Vector3f min, max;
  object.Bounds(min, max);
  target = world_from_object * ((min + max) / 2).cast<double>();
  const auto& fixture = robot::testing::Fixture("ur5");
  robot_registry::RobotUpload upload;
  upload.urdf_path = fixture.urdf_path;
  upload.base_link = fixture.base_link;
  upload.tip_link = fixture.tip_link;
  upload.files = robot::testing::FixtureBundleFiles("ur5");
  const auto robot = Must(world.context().robots.AddRobot(upload));
  store::MountRecord mount;
  mount.scene_id = scene_id;
  mount.robot_id = robot.robot_id;
  Pose3 base = Pose3::Identity();
  base.linear() = Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  base.translation() = Eigen::Vector3d(0.55, 0.0, 0.0);
  mount.base_pose = base.matrix();
  if (encoder_sigma > 0) mount.encoder_sigma = {encoder_sigma};
  mount_id = Must(world.context().robots.AddMount(mount)).first.mount_id;
}

CampaignViewpoint ModelWorld::ViewpointAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  CampaignViewpoint viewpoint;
  viewpoint.position = position;
  viewpoint.target = target;
  viewpoint.goal = robot::LookAtGoal(position, target, "viewpoint").value();
  return viewpoint;
}

CampaignViewpoint ModelWorld::Viewpoint(double distance, double elevation_deg, double azimuth_deg) const {
  const double el = elevation_deg * std::numbers::pi / 180.0;
  const double az = azimuth_deg * std::numbers::pi / 180.0;
  const Eigen::Vector3d direction(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  return ViewpointAt(target + distance * direction, target);
}

CampaignPlan ModelWorld::Campaign(std::vector<CampaignViewpoint> viewpoints, uint32_t rotations, bool encoder_noise,
                                  double start_angle_deg) const {
  CampaignPlan plan;
  plan.scene_id = scene_id;
  plan.mount_id = mount_id;
  plan.name = "block";
  plan.seed = 11;
  plan.viewpoints = std::move(viewpoints);
  plan.rotations = rotations;
  plan.start_angle_deg = start_angle_deg;
  plan.rotation_step_deg = 360.0 / rotations;
  plan.apply_encoder_noise = encoder_noise;
  plan.scan.camera = sensor::CameraFromFov(320, 240, 40.0, 0.05, 3.0);
  plan.scan.fields = kFieldPosition | kFieldPixel;
  plan.scan.measurement.fields = plan.scan.fields;
  return plan;
}

std::string ModelWorld::RunCampaign(const CampaignPlan& plan) {
  const auto job = RunCampaignJob(plan);
  EXPECT_EQ(job->end_state, store::JobState::kSucceeded) << job->end_message;
  return job->job_id;
}

std::unique_ptr<StoredJob> ModelWorld::RunCampaignJob(const CampaignPlan& plan, jobs::JobControl* control) {
  EXPECT_TRUE(CheckCampaignWorld(world.context(), plan, false).ok());
  auto job = std::make_unique<StoredJob>(world, "campaign");
  jobs::JobControl own;
  service::RunCampaign(world.context(), *job, job->job_id, plan, control ? *control : own);
  CampaignRecord record;
  record.job_id = job->job_id;
  record.kind = "campaign";
  record.scene_id = plan.scene_id;
  record.mount_id = plan.mount_id;
  record.encoder_noise = plan.apply_encoder_noise;
  record.scans = job->scans;
  campaigns.Add(record);
  return job;
}

TriangleMesh Bunny() {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto mesh = geometry::ImportMesh(bytes, geometry::MeshFileFormat::kPly, 1.0);
  EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
  return mesh.ok() ? std::move(mesh).value() : TriangleMesh();
}

Pose3 BunnyUpright() { return Pose3(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX())); }

std::vector<std::string> ModelWorld::CloudsOf(const std::string& campaign_job_id) {
  std::vector<store::CloudRecord> clouds = Must(world.clouds().List("", 1000, campaign_job_id));
  // Scan names sort as the campaign captured them (rotation-major).
  std::sort(clouds.begin(), clouds.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::vector<std::string> ids;
  for (const auto& cloud : clouds) ids.push_back(cloud.cloud_id);
  return ids;
}

std::unique_ptr<StoredJob> ModelWorld::RunModel(const ModelRequest& request, jobs::JobControl* control) {
  auto job = std::make_unique<StoredJob>(world, "model");
  auto plan = PlanModel(world.context(), campaigns, request);
  if (!plan.ok()) {
    ADD_FAILURE() << plan.status().ToString();
    return job;
  }
  jobs::JobControl own;
  service::RunModel(world.context(), *job, job->job_id, *plan, control ? *control : own);
  return job;
}

}  // namespace vscan::service::testing
