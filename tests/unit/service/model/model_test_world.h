#pragma once
// The world of the model-job tests: a UR5 beside a rotary table with an L-shaped block on it;
// campaigns run through the service layer with their scans stored as vscand stores them (blobs,
// artifact rows, cloud rows), and model jobs run over those clouds.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "api/reports/proto_report_writer.h"
#include "jobs/job_runner.h"
#include "service/campaign/campaign_plan.h"
#include "service/job/job_events.h"
#include "service/model/campaign_records.h"
#include "service/model/model_plan.h"
#include "service_world.h"
#include "model_test_block.h"

namespace vscan::service::testing {

// A job's events and artifacts kept in the world's store, and for the test to read.
class StoredJob final : public JobRecorder {
 public:
  StoredJob(ServiceWorld& world, const std::string& kind);

  Status Record(const JobEventUpdate& update) override;
  StatusOr<std::string> RecordArtifact(const std::string& name, const std::string& media_type,
                                       const std::string& bytes, const ScanArtifact* scan,
                                       const store::CloudRecord* cloud, const JobEventUpdate& update) override;
  Status End(const JobEventUpdate& update) override;
  // Reports print as vscand prints them.
  const ReportWriter& reports() const override { return reports_; }

  std::string job_id;
  std::vector<std::string> messages;
  std::vector<ScanAlignmentRecord> alignments;  // as the events carried them
  std::map<std::string, std::string> artifacts;  // name -> bytes
  std::vector<CampaignScanRecord> scans;
  std::vector<uint32_t> steps_done;
  store::JobState end_state = store::JobState::kRunning;
  std::string end_message;

 private:
  store::JobProgress Progress(const JobEventUpdate& update);
  ServiceWorld& world_;
  uint64_t sequence_ = 0;
  api::ProtoReportWriter reports_;
};

class TestCampaignRecords final : public CampaignRecords {
 public:
  explicit TestCampaignRecords(ServiceWorld& world) : world_(world) {}
  void Add(const CampaignRecord& record) { records_[record.job_id] = record; }
  StatusOr<CampaignRecord> Get(const std::string& job_id) override;

 private:
  ServiceWorld& world_;
  std::map<std::string, CampaignRecord> records_;
};

// The Stanford bunny (metres) and the pose that stands it on the table (its +y turned to +z):
// curved, with features to match.
TriangleMesh Bunny();
Pose3 BunnyUpright();

class ModelWorld {
 public:
  // object (metres) stands on the table at world_from_object; encoder_sigma (radians, every joint)
  // is the arm's encoder noise a campaign may apply.
  explicit ModelWorld(double encoder_sigma = 0.0, const TriangleMesh& object = LBlock(),
                      const Pose3& world_from_object = Pose3::Identity());

  ServiceWorld world;
  std::string scene_id;
  std::string mount_id;
  TestCampaignRecords campaigns{world};

  // The middle of the object's bounding box, where viewpoints look.
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  // A viewpoint `distance` from the object's middle at elevation_deg, on the arm's side (+x).
  CampaignViewpoint Viewpoint(double distance, double elevation_deg, double azimuth_deg = 0.0) const;
  static CampaignViewpoint ViewpointAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target);

  // viewpoints x rotations (evenly over a turn), a 320 x 240 camera storing positions and pixels.
  CampaignPlan Campaign(std::vector<CampaignViewpoint> viewpoints, uint32_t rotations, bool encoder_noise = false,
                        double start_angle_deg = 0.0) const;
  // Runs the campaign to its end; returns its job id (its records known to `campaigns`).
  std::string RunCampaign(const CampaignPlan& plan);
  // The same, returning the job's events and artifacts.
  std::unique_ptr<StoredJob> RunCampaignJob(const CampaignPlan& plan, jobs::JobControl* control = nullptr);
  // The clouds a campaign stored, in the order it captured them.
  std::vector<std::string> CloudsOf(const std::string& campaign_job_id);
  // Plans and runs a model job; a plan the request does not pass fails the test.
  std::unique_ptr<StoredJob> RunModel(const ModelRequest& request, jobs::JobControl* control = nullptr);
};

}  // namespace vscan::service::testing
