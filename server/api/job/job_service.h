#pragma once
// JobService: scan campaigns and model jobs as durable jobs run by the job runner; get, list,
// cancel, watch them and read what they produced.

#include <functional>
#include <mutex>
#include <string>

#include "api/job/job_tracker.h"
#include "guards/stall_watchdog.h"
#include "service/context/service_context.h"
#include "service/job/job_events.h"
#include "service/picking/estimates_inbox.h"
#include "service/picking/picking_session.h"
#include "jobs/job_runner.h"
#include "vscan/v1/job.grpc.pb.h"

namespace vscan::api {

class JobService final : public v1::JobService::CallbackService {
 public:
  // stalled_readers cancels WatchJob and ReadArtifact streams whose client stopped reading; null
  // watches nothing.
  JobService(service::ServiceContext& context, JobTracker& tracker, jobs::JobRunner& runner,
             guards::StallWatchdog* stalled_readers)
      : context_(context), tracker_(tracker), runner_(runner), stalled_readers_(stalled_readers) {}

  grpc::ServerUnaryReactor* StartCampaign(grpc::CallbackServerContext* ctx, const v1::StartCampaignRequest* request,
                                          v1::StartCampaignResponse* response) override;
  grpc::ServerUnaryReactor* StartModel(grpc::CallbackServerContext* ctx, const v1::StartModelRequest* request,
                                       v1::StartModelResponse* response) override;
  grpc::ServerUnaryReactor* StartBinFill(grpc::CallbackServerContext* ctx, const v1::StartBinFillRequest* request,
                                         v1::StartBinFillResponse* response) override;
  // In dataset_job_service.cpp.
  grpc::ServerUnaryReactor* StartDataset(grpc::CallbackServerContext* ctx, const v1::StartDatasetRequest* request,
                                         v1::StartDatasetResponse* response) override;
  // In picking/picking_job_service.cpp.
  grpc::ServerUnaryReactor* StartPicking(grpc::CallbackServerContext* ctx, const v1::StartPickingRequest* request,
                                         v1::StartPickingResponse* response) override;
  // In picking/picking_estimates_service.cpp.
  grpc::ServerUnaryReactor* SubmitPickingEstimates(grpc::CallbackServerContext* ctx,
                                                   const v1::SubmitPickingEstimatesRequest* request,
                                                   v1::SubmitPickingEstimatesResponse* response) override;
  // In dataset_score_service.cpp.
  grpc::ServerUnaryReactor* ScoreDatasetResults(grpc::CallbackServerContext* ctx,
                                                const v1::ScoreDatasetResultsRequest* request,
                                                v1::ScoreDatasetResultsResponse* response) override;
  grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* ctx, const v1::GetJobRequest* request,
                                   v1::GetJobResponse* response) override;
  grpc::ServerUnaryReactor* ListJobs(grpc::CallbackServerContext* ctx, const v1::ListJobsRequest* request,
                                     v1::ListJobsResponse* response) override;
  grpc::ServerUnaryReactor* CancelJob(grpc::CallbackServerContext* ctx, const v1::CancelJobRequest* request,
                                      v1::CancelJobResponse* response) override;
  // In job_resume.cpp.
  grpc::ServerUnaryReactor* ResumeJob(grpc::CallbackServerContext* ctx, const v1::ResumeJobRequest* request,
                                      v1::ResumeJobResponse* response) override;
  grpc::ServerUnaryReactor* DeleteJob(grpc::CallbackServerContext* ctx, const v1::DeleteJobRequest* request,
                                      v1::DeleteJobResponse* response) override;
  grpc::ServerWriteReactor<v1::WatchJobResponse>* WatchJob(grpc::CallbackServerContext* ctx,
                                                           const v1::WatchJobRequest* request) override;
  grpc::ServerWriteReactor<v1::ReadArtifactResponse>* ReadArtifact(grpc::CallbackServerContext* ctx,
                                                                   const v1::ReadArtifactRequest* request) override;

 private:
  // ResumeJob for a picking job (in picking/picking_job_service.cpp).
  Status ResumePicking(const store::JobRecord& ended, v1::ResumeJobResponse* response);
  // What a picking job of plan does (a start or a resume).
  using PickingJobRun = std::function<void(service::JobRecorder&, const std::string&, jobs::JobControl&)>;
  PickingJobRun PickingRun(std::shared_ptr<const service::PickingPlan> plan, std::string name, std::string bin_job_id);
  // Sets job.awaiting_estimates while a client-perception picking job waits for a step's estimates
  // (in picking/picking_estimates_service.cpp).
  void ShowAwaitedEstimates(v1::Job* job) const;
  // What a started job does on the runner's thread.
  using JobRun = std::function<void(service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl&)>;
  // The start every kind shares, under the admission lock: refuses when max_queued_jobs wait
  // (the error names field), then record() creates or reopens the job and returns its id, then
  // run is queued as that job.
  Status Admit(const std::string& field, const std::function<StatusOr<std::string>()>& record, JobRun run);
  // Records a QUEUED job of kind into out; returns its id.
  StatusOr<std::string> CreateJob(service::JobKind kind, const std::string& name,
                                  const google::protobuf::MessageLite& spec, uint32_t steps_total, v1::Job* out);
  // Queues work as job_id under the queue bound; false (the job then ended) when the runner stops.
  Status Submit(const std::string& job_id, std::function<void(jobs::JobControl&)> run);

  service::ServiceContext& context_;
  JobTracker& tracker_;
  jobs::JobRunner& runner_;
  guards::StallWatchdog* stalled_readers_;
  // Makes the queue check, the job's creation and its submission one step, so that the queue
  // bound holds under concurrent starts and no cancel falls between creation and submission.
  std::mutex admit_mutex_;
  // Where client-perception picking jobs wait for estimates.
  service::EstimatesInbox picking_estimates_;
};

}  // namespace vscan::api
