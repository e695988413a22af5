#pragma once
// Runs a planned model job on a job-runner thread: alignment (an event per scan), the union as
// aligned.ply, reconstruction (mesh.ply), evaluation against the ground truth (uncovered.ply,
// coverage.png, next best views), and model.json when the job ends, however it ends.

#include <cstdint>
#include <memory>
#include <string>

#include "jobs/job_runner.h"
#include "service/job/job_events.h"
#include "service/model/model_plan.h"
#include "service/context/service_context.h"
#include "vscan/common/point_cloud.h"

namespace vscan::service {

// Events and artifacts go to recorder; job_id names the job in logs and in model.json.
void RunModel(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const ModelPlan& plan,
              jobs::JobControl& control);

// The work items a model job reports progress in: one per cloud, the union, and one per later stage.
uint32_t ModelStepsTotal(const ModelPlan& plan);

// The steps a campaign adds to its own when it models its scans (the union and the later stages).
uint32_t CampaignModelSteps(const ModelPlan& plan);

class ModelRun;

// The model stages of a campaign that aligns its scans as it captures them: Prepare before the
// first scan, AlignCaptured after each scan is stored, Complete when scanning ends (the later
// stages read the scans back as stored), and WriteReport (model.json) however the campaign ends.
// Events go to the campaign's recorder; steps_done is the campaign's count so far.
class CampaignModel {
 public:
  CampaignModel(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, ModelPlan plan,
                jobs::JobControl& control);
  ~CampaignModel();
  CampaignModel(const CampaignModel&) = delete;
  CampaignModel& operator=(const CampaignModel&) = delete;

  Status Prepare();
  // cloud describes the scan as the campaign stored it (its name, poses, camera, table angle).
  Status AlignCaptured(ModelCloud cloud, const PointCloud& points, uint32_t steps_done);
  Status Complete(uint32_t steps_done);
  void WriteReport(store::JobState state);
  std::string Summary() const;
  const ModelPlan& plan() const;

 private:
  std::unique_ptr<ModelRun> run_;
};

}  // namespace vscan::service
