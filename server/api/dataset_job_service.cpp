// JobService.StartDataset: a dataset plan checked, then written by a job on the job runner.

#include <spdlog/spdlog.h>

#include "api/dataset_spec.h"
#include "api/job_recorder.h"
#include "api/job_service.h"
#include "api/unary.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/dataset_directories.h"

namespace vscan::api {

grpc::ServerUnaryReactor* JobService::StartDataset(grpc::CallbackServerContext* ctx,
                                                   const v1::StartDatasetRequest* request,
                                                   v1::StartDatasetResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartDataset", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    ASSIGN_OR_RETURN(ValidatedDataset validated, ValidateDataset(request->spec(), context_, tracker_.catalogue()));
    if (request->validate_only()) return Status::Ok();
    const uint32_t max_queued = context_.options.limits.max_queued_jobs;
    std::lock_guard admit(admit_mutex_);
    if (runner_.queued() >= max_queued) {
      return ResourceExhausted("spec: " + std::to_string(max_queued) + " jobs already wait to run; retry later");
    }
    // The resumed job was read before the lock: a delete since then may have taken its directory.
    std::unique_lock<std::mutex> names;
    if (context_.dataset_directories) names = context_.dataset_directories->HoldNames();
    if (const std::string& resumed = request->spec().resume_job_id(); !resumed.empty()) {
      const StatusOr<store::JobRecord> still = tracker_.catalogue().GetJob(resumed);
      if (!still.ok() && still.status().code() == StatusCode::kNotFound) {
        return NotFound("spec.resume_job_id", "no job '" + resumed + "' (deleted meanwhile)");
      }
      RETURN_IF_ERROR(still.status());
    }
    const service::dataset::DatasetPlan& plan = validated.setup->plan;
    const auto total = static_cast<uint32_t>(service::dataset::SceneCount(plan));
    ASSIGN_OR_RETURN(v1::Job job, tracker_.CreateDataset(validated.spec, plan.name, total));
    const std::string job_id = job.job_id();
    auto work = std::make_shared<const service::DatasetJob>(
        service::DatasetJob{validated.setup, DatasetRootOf(validated.spec, job_id, context_.options),
                            DatasetDirectoryId(validated.spec, job_id), context_.dataset_directories,
                            service::DatasetTarBound(context_.options.limits.max_request_memory_bytes)});
    RETURN_IF_ERROR(Submit(job_id, [this, job_id, work](jobs::JobControl& control) {
      TrackedJobRecorder recorder(tracker_, job_id);
      service::RunDatasetJob(recorder, job_id, *work, control);
    }));
    spdlog::info("job {}: dataset of {} scenes into {} queued", job_id, total, work->root.string());
    *response->mutable_job() = std::move(job);
    return Status::Ok();
  });
}

}  // namespace vscan::api
