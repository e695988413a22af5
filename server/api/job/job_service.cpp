#include "api/job/job_service.h"

#include <algorithm>
#include <memory>

#include <spdlog/spdlog.h>

#include "api/bins/bin_fill_spec.h"
#include "api/campaign/campaign_spec.h"
#include "api/job/job_convert.h"
#include "api/job/job_recorder.h"
#include "api/model/catalogue_campaign_records.h"
#include "api/model/model_spec.h"
#include "service/bins/bin_fill_run.h"
#include "service/campaign/campaign_run.h"
#include "service/job/run_end.h"
#include "service/model/model_run.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"

namespace vscan::api {
namespace {

// "SUCCEEDED" for JOB_STATE_SUCCEEDED.
std::string StateName(v1::JobState state) { return v1::JobState_Name(state).substr(10); }

bool Ended(v1::JobState state) { return state != v1::JOB_STATE_QUEUED && state != v1::JOB_STATE_RUNNING; }

// A ListJobs page stays within what a client with gRPC's default 4 MiB receive limit accepts.
constexpr size_t kMaxListBytes = 3u << 20;
constexpr int kListBatch = 16;

}  // namespace

grpc::ServerUnaryReactor* JobService::StartCampaign(grpc::CallbackServerContext* ctx,
                                                    const v1::StartCampaignRequest* request,
                                                    v1::StartCampaignResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartCampaign", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    const v1::CampaignSpec& spec = request->spec();
    ASSIGN_OR_RETURN(service::CampaignPlan validated, ValidateCampaign(spec, context_, request->validate_only()));
    if (request->validate_only()) return Status::Ok();
    auto plan = std::make_shared<const service::CampaignPlan>(std::move(validated));
    v1::Job* job = response->mutable_job();
    RETURN_IF_ERROR(Admit(
        "spec", [&] { return CreateJob(service::JobKind::kCampaign, spec.name(), spec, plan->steps_total(), job); },
        [this, plan](service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl& control) {
          service::RunCampaign(context_, recorder, job_id, *plan, control);
        }));
    spdlog::info("job {}: campaign of {} scans queued", job->job_id(), plan->steps_total());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* JobService::StartModel(grpc::CallbackServerContext* ctx, const v1::StartModelRequest* request,
                                                 v1::StartModelResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartModel", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    CatalogueCampaignRecords campaigns(tracker_.catalogue(), context_.options.limits);
    ASSIGN_OR_RETURN(service::ModelPlan validated, ValidateModel(request->spec(), context_, campaigns));
    if (request->validate_only()) return Status::Ok();
    auto plan = std::make_shared<const service::ModelPlan>(std::move(validated));
    v1::Job* job = response->mutable_job();
    const uint32_t total = service::ModelStepsTotal(*plan);
    const v1::ModelSpec& spec = request->spec();
    RETURN_IF_ERROR(Admit(
        "spec", [&] { return CreateJob(service::JobKind::kModel, spec.name(), spec, total, job); },
        [this, plan](service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl& control) {
          service::RunModel(context_, recorder, job_id, *plan, control);
        }));
    spdlog::info("job {}: model job over {} clouds queued", job->job_id(), plan->clouds.size());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* JobService::StartBinFill(grpc::CallbackServerContext* ctx,
                                                   const v1::StartBinFillRequest* request,
                                                   v1::StartBinFillResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartBinFill", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    const v1::BinFillSpec& spec = request->spec();
    ASSIGN_OR_RETURN(service::BinFillPlan validated, ValidateBinFill(spec, context_, request->validate_only()));
    if (request->validate_only()) return Status::Ok();
    auto plan = std::make_shared<const service::BinFillPlan>(std::move(validated));
    v1::Job* job = response->mutable_job();
    const auto total = static_cast<uint32_t>(plan->parts_total());
    RETURN_IF_ERROR(Admit(
        "spec", [&] { return CreateJob(service::JobKind::kBinFill, spec.name(), spec, total, job); },
        [this, plan](service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl& control) {
          service::RunBinFill(context_.registry, recorder, job_id, *plan, control);
        }));
    spdlog::info("job {}: bin fill of {} parts into scene {} queued", job->job_id(), total, plan->request.scene_id);
    return Status::Ok();
  });
}

StatusOr<std::string> JobService::CreateJob(service::JobKind kind, const std::string& name,
                                            const google::protobuf::MessageLite& spec, uint32_t steps_total,
                                            v1::Job* out) {
  ASSIGN_OR_RETURN(*out, tracker_.Create(kind, name, spec, steps_total));
  return out->job_id();
}

Status JobService::Admit(const std::string& field, const std::function<StatusOr<std::string>()>& record, JobRun run) {
  const uint32_t max_queued = context_.options.limits.max_queued_jobs;
  std::lock_guard admit(admit_mutex_);
  if (runner_.queued() >= max_queued) {
    return ResourceExhausted(field + ": " + std::to_string(max_queued) + " jobs already wait to run; retry later");
  }
  ASSIGN_OR_RETURN(const std::string job_id, record());
  return Submit(job_id, [this, job_id, run = std::move(run)](jobs::JobControl& control) {
    TrackedJobRecorder recorder(tracker_, job_id);
    run(recorder, job_id, control);
  });
}

Status JobService::Submit(const std::string& job_id, std::function<void(jobs::JobControl&)> run) {
  auto work = [this, job_id, run = std::move(run)](jobs::JobControl& control) {
    try {
      run(control);
    } catch (const std::exception& e) {
      JobEventUpdate update;
      update.state = store::JobState::kFailed;
      update.message = std::string("unexpected error: ") + e.what();
      const Status ended = tracker_.End(job_id, update);
      if (!ended.ok()) spdlog::error("job {}: {}", job_id, ended.ToString());
    }
  };
  auto dropped = [this, job_id](jobs::StopReason reason) {
    JobEventUpdate update;
    update.state = service::StoppedState(reason);
    update.message = reason == jobs::StopReason::kCancelled ? "cancelled before it started"
                                                            : service::StoppedMessage(update.state);
    const Status ended = tracker_.End(job_id, update);
    if (!ended.ok()) spdlog::error("job {}: {}", job_id, ended.ToString());
  };
  if (!runner_.Submit(job_id, std::move(work), dropped, context_.options.limits.max_queued_jobs)) {
    dropped(jobs::StopReason::kShutdown);
    return Unavailable("server is shutting down");
  }
  return Status::Ok();
}

grpc::ServerUnaryReactor* JobService::GetJob(grpc::CallbackServerContext* ctx, const v1::GetJobRequest* request,
                                             v1::GetJobResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetJob", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->job_id(), "job_id"));
    ASSIGN_OR_RETURN(*response->mutable_job(), tracker_.Get(request->job_id()));
    ShowAwaitedEstimates(response->mutable_job());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* JobService::ListJobs(grpc::CallbackServerContext* ctx, const v1::ListJobsRequest* request,
                                               v1::ListJobsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListJobs", [&]() -> Status {
    ASSIGN_OR_RETURN(int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "job_"));
    // Jobs carry every artifact, so a page is also cut at a byte budget (at least one job), read
    // from the catalogue a few jobs at a time.
    std::string after = request->page_token();
    size_t bytes = 0;
    bool more = false;
    while (response->jobs_size() < limit) {
      const int batch = std::min(kListBatch, limit - response->jobs_size());
      ASSIGN_OR_RETURN(auto jobs, tracker_.catalogue().ListJobs(after, batch + 1));
      more = static_cast<int>(jobs.size()) > batch;
      if (more) jobs.resize(batch);
      for (const auto& record : jobs) {
        v1::Job job;
        RETURN_IF_ERROR(ToProto(record, &job));
        ShowAwaitedEstimates(&job);
        bytes += job.ByteSizeLong();
        if (response->jobs_size() > 0 && bytes > kMaxListBytes) {
          more = true;
          break;
        }
        *response->add_jobs() = std::move(job);
      }
      if (!more || bytes > kMaxListBytes) break;
      after = response->jobs().rbegin()->job_id();
    }
    if (more) response->set_next_page_token(response->jobs().rbegin()->job_id());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* JobService::CancelJob(grpc::CallbackServerContext* ctx, const v1::CancelJobRequest* request,
                                                v1::CancelJobResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "CancelJob", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->job_id(), "job_id"));
    ASSIGN_OR_RETURN(const v1::Job before, tracker_.Get(request->job_id()));
    if (Ended(before.state())) {
      return FailedPrecondition("job_id: job '" + request->job_id() + "' has already ended (" +
                                StateName(before.state()) + ")");
    }
    {
      // A job being started is in the catalogue before it is in the runner's queue.
      std::lock_guard admit(admit_mutex_);
      runner_.Cancel(request->job_id());
    }
    ASSIGN_OR_RETURN(*response->mutable_job(), tracker_.Get(request->job_id()));
    ShowAwaitedEstimates(response->mutable_job());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* JobService::DeleteJob(grpc::CallbackServerContext* ctx, const v1::DeleteJobRequest* request,
                                                v1::DeleteJobResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "DeleteJob", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->job_id(), "job_id"));
    ASSIGN_OR_RETURN(const store::CollectedBlobs removed, tracker_.Delete(request->job_id()));
    spdlog::info("job {}: deleted ({} files, {} bytes freed)", request->job_id(), removed.files, removed.bytes);
    response->set_removed_files(removed.files);
    response->set_removed_bytes(removed.bytes);
    return Status::Ok();
  });
}

}  // namespace vscan::api
