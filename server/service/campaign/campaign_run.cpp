#include "service/campaign/campaign_run.h"
#include "service/job/run_end.h"

#include <cstdio>
#include <optional>

#include <spdlog/spdlog.h>

#include "service/campaign/campaign_step.h"
#include "service/campaign/campaign_summary.h"
#include "service/clouds/cloud_store.h"
#include "service/model/model_run.h"
#include "service/model/pose_prior.h"
#include "vscan/common/cloud_io.h"
#include "service/job/message_numbers.h"

namespace vscan::service {
namespace {

constexpr const char* kPlyMediaType = "model/ply";
constexpr const char* kJsonMediaType = "application/json";

std::string Where(uint32_t viewpoint, double angle_deg) {
  return "viewpoint " + std::to_string(viewpoint) + " at " + Number(angle_deg) + " deg";
}

class CampaignRun {
 public:
  CampaignRun(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const CampaignPlan& plan,
              jobs::JobControl& control, const StoredCampaignScans& stored)
      : context_(context), recorder_(recorder), job_id_(job_id), plan_(plan), control_(control), stored_(stored) {}

  void Run() {
    const uint32_t total = plan_.scans_total();
    Status status = Event(std::to_string(total) + " scans planned (" + std::to_string(plan_.viewpoints.size()) +
                          " viewpoints x " + std::to_string(plan_.rotations) + " rotations)" +
                          (plan_.model ? ModelIntent(*plan_.model) : "") +
                          (stored_.empty() ? "" : "; resumed, " + std::to_string(stored_.size()) + " scans stored"));
    if (status.ok() && plan_.model) {
      model_.emplace(context_, recorder_, job_id_, *plan_.model, control_);
      status = model_->Prepare();
    }
    if (status.ok()) status = Steps();
    if (status.ok() && model_ && !control_.stop_requested()) {
      status = model_->Complete(static_cast<uint32_t>(records_.size()));
      if (status.ok()) model_steps_done_ = plan_.model_steps;
    }
    store::JobState state = store::JobState::kSucceeded;
    std::string message;
    if (control_.stop_requested()) {
      state = StoppedState(control_.reason());
      message = StoppedMessage(state) + " after " + std::to_string(records_.size()) + " of " + std::to_string(total) + " steps";
    } else if (!status.ok()) {
      state = store::JobState::kFailed;
      message = status.message();
    } else {
      message = "campaign done: " + std::to_string(captured_) + " scans captured, " +
                std::to_string(records_.size() - captured_) + " steps skipped";
      if (model_) message += "; " + model_->Summary();
    }
    WriteSummary(state);
    if (model_) model_->WriteReport(state);
    RecordEnd(recorder_, job_id_, Update(state, message, false));
  }

 private:
  JobEventUpdate Update(store::JobState state, const std::string& message, bool reached) const {
    JobEventUpdate update;
    update.state = state;
    update.message = message;
    update.steps_done = static_cast<uint32_t>(records_.size()) + model_steps_done_;
    update.step = records_.empty() ? 0 : records_.back().step;
    update.pose_reached = reached;
    return update;
  }

  Status Event(const std::string& message, bool reached = false) {
    return recorder_.Record(Update(store::JobState::kRunning, message, reached));
  }

  Status Steps() {
    ASSIGN_OR_RETURN(const robot_registry::MountedRobot mounted, context_.robots.Mount(plan_.mount_id));
    std::vector<std::optional<ViewpointSolution>> solutions(plan_.viewpoints.size());
    const auto viewpoints = static_cast<uint32_t>(plan_.viewpoints.size());
    for (uint32_t r = 0; r < plan_.rotations; ++r) {
      for (uint32_t v = 0; v < viewpoints; ++v) {
        if (control_.stop_requested()) return Status::Ok();
        const double angle = plan_.AngleDeg(r);
        if (auto stored = stored_.find(r * viewpoints + v); stored != stored_.end()) {
          RETURN_IF_ERROR(PassOver(stored->second));
          continue;
        }
        if (!solutions[v]) {
          auto solved = SolveViewpoint(mounted, plan_.viewpoints[v]);
          if (!solved.ok()) return Status(solved.status().code(), Where(v, angle) + ": " + solved.status().message());
          solutions[v] = std::move(solved).value();
        }
        const uint32_t step = r * viewpoints + v;
        auto result = RunStep(context_, plan_, *solutions[v], angle, StepSeed(plan_.seed, step),
                              control_.flag());
        if (control_.stop_requested()) return Status::Ok();
        if (!result.ok()) return Status(result.status().code(), Where(v, angle) + ": " + result.status().message());
        RETURN_IF_ERROR(Record(step, r, v, angle, *solutions[v], std::move(result).value()));
      }
    }
    return Status::Ok();
  }

  std::string CapturedMessage(const CampaignStepRecord& record) const {
    return "scan " + std::to_string(captured_) + " captured (step " + std::to_string(record.step + 1) + " of " +
           std::to_string(plan_.scans_total()) + "): " + Where(record.viewpoint_index, record.table_angle_deg) + ", " +
           std::to_string(record.points) + " points";
  }

  // A step an earlier run stored: counted and reported as it was, not scanned again; a campaign
  // that models its scans aligns it read back from the store.
  Status PassOver(const StoredCampaignScan& stored) {
    CampaignStepRecord record = stored.record;
    record.seed = StepSeed(plan_.seed, record.step);
    record.outcome = "captured";
    record.has_arm = true;
    ++captured_;
    record.message = CapturedMessage(record);
    records_.push_back(record);
    if (!model_) return Status::Ok();
    ASSIGN_OR_RETURN(const std::string ply, context_.blobs.Get(stored.sha256));
    auto points = ParsePly(ply, record.file, ply.size());
    if (!points.ok()) {
      return Status(points.status().code(), "cannot read " + record.file + ": " + points.status().message());
    }
    const store::CloudRecord cloud = ScanCloud(record, points->fields);
    return model_->AlignCaptured(ModelCloudOf(cloud, record), *points, static_cast<uint32_t>(records_.size()));
  }

  Status Record(uint32_t step, uint32_t r, uint32_t v, double angle, const ViewpointSolution& solution,
                StepResult result) {
    CampaignStepRecord record;
    record.step = step;
    record.rotation_index = r;
    record.viewpoint_index = v;
    record.table_angle_deg = angle;
    record.seed = result.seed;
    switch (result.outcome) {
      case StepResult::Outcome::kUnreachable:
        record.outcome = "unreachable";
        record.miss_distance = solution.miss_distance;
        record.message = Where(v, angle) + ": unreachable, misses by " + Number(solution.miss_distance) + " m";
        records_.push_back(record);
        return Event(record.message);
      case StepResult::Outcome::kCollision:
        record.outcome = "collision";
        record.has_arm = true;
        record.arm = result.arm;
        record.message = Where(v, angle) + ": skipped, " + result.collision;
        records_.push_back(record);
        return Event(record.message, true);
      case StepResult::Outcome::kCaptured: break;
    }
    record.outcome = "captured";
    record.has_arm = true;
    record.arm = result.arm;
    record.points = result.cloud.size();
    record.rejected_dark = result.rejected_dark;
    record.rejected_saturated = result.rejected_saturated;
    record.file = ScanArtifactName(r, v);
    ASSIGN_OR_RETURN(const std::string ply, EncodePly(result.cloud));
    const store::CloudRecord cloud = ScanCloud(record, result.cloud.fields);
    ++captured_;
    record.message = CapturedMessage(record);
    records_.push_back(record);
    const ScanArtifact scan = ScanArtifactOf(record);
    auto artifact = recorder_.RecordArtifact(record.file, kPlyMediaType, ply, &scan, &cloud,
                                             Update(store::JobState::kRunning, record.message, true));
    if (!artifact.ok()) {
      return Status(artifact.status().code(), "cannot store " + record.file + ": " + artifact.status().message());
    }
    records_.back().artifact_id = *artifact;
    if (!model_) return Status::Ok();
    return model_->AlignCaptured(ModelCloudOf(cloud, record), result.cloud, static_cast<uint32_t>(records_.size()));
  }

  // The scan as the model stages see it: where the arm was told to put the sensor, the table it
  // was turned on.
  ModelCloud ModelCloudOf(const store::CloudRecord& cloud, const CampaignStepRecord& record) const {
    ModelCloud model;
    model.record = cloud;
    model.record.origin = store::CloudOrigin::kCampaignScan;  // the recorder sets it on the stored row
    model.label = record.file;
    model.commanded_world_from_sensor = record.arm.commanded_pose;
    const auto& scene = plan_.model->scene;
    if (scene && scene->table.enabled) model.table = scene->table;
    if (auto mounted = context_.robots.Mount(plan_.mount_id); mounted.ok()) {
      auto information = CommandedPoseInformation(*mounted, record.arm.commanded, plan_.apply_encoder_noise);
      if (information.ok()) model.initial_information = *information;
    }
    return model;
  }

  static std::string ModelIntent(const ModelPlan& model) {
    std::string text = model.align ? "; each aligned as it is captured" : "; taken at their poses";
    if (model.reconstruct) text += model.reconstruction == ReconstructionKind::kTsdf ? ", TSDF" : ", Poisson";
    if (model.evaluate) text += ", evaluated";
    return text;
  }

  // The stored cloud a captured scan also is: where the arm put the sensor, the plan's camera.
  store::CloudRecord ScanCloud(const CampaignStepRecord& record, uint32_t fields) const {
    store::CloudRecord cloud;
    cloud.name = record.file;
    cloud.points = record.points;
    cloud.fields = fields;
    cloud.scene_id = plan_.scene_id;
    const bool sensor_frame = plan_.scan.frame == raycast::ScanFrame::kSensor;
    cloud.frame = sensor_frame ? store::CloudFrame::kSensor : store::CloudFrame::kWorld;
    cloud.world_from_sensor = record.arm.achieved_pose.matrix();
    cloud.camera = ToCloudCamera(plan_.scan.camera);
    cloud.table_angle_deg = record.table_angle_deg;
    return cloud;
  }

  void WriteSummary(store::JobState state) {
    const std::string json = recorder_.reports().CampaignJson(job_id_, store::JobStateName(state), plan_, records_);
    auto written = recorder_.RecordArtifact("campaign.json", kJsonMediaType, json, nullptr, nullptr,
                                            Update(store::JobState::kRunning, "campaign.json written", false));
    if (!written.ok()) spdlog::error("job {}: cannot store campaign.json: {}", job_id_, written.status().ToString());
  }

  ServiceContext& context_;
  JobRecorder& recorder_;
  const std::string job_id_;
  const CampaignPlan& plan_;
  jobs::JobControl& control_;
  const StoredCampaignScans& stored_;
  std::vector<CampaignStepRecord> records_;
  uint32_t captured_ = 0;
  std::optional<CampaignModel> model_;
  uint32_t model_steps_done_ = 0;
};

}  // namespace

std::string ScanArtifactName(uint32_t rotation, uint32_t viewpoint) {
  char name[64];
  std::snprintf(name, sizeof(name), "scan-r%02u-v%02u.ply", rotation, viewpoint);
  return name;
}

void RunCampaign(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const CampaignPlan& plan,
                 jobs::JobControl& control, const StoredCampaignScans& stored) {
  CampaignRun(context, recorder, job_id, plan, control, stored).Run();
}

}  // namespace vscan::service
