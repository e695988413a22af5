// JobService.StartDataset: a dataset plan checked, then written by a job on the job runner.

#include <spdlog/spdlog.h>

#include "api/datasets/dataset_spec.h"
#include "api/job/job_service.h"
#include "api/transport/unary.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/dataset_directories.h"

namespace vscan::api {

grpc::ServerUnaryReactor* JobService::StartDataset(grpc::CallbackServerContext* ctx,
                                                   const v1::StartDatasetRequest* request,
                                                   v1::StartDatasetResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartDataset", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    if (request->list_mesh_files()) {
      if (request->validate_only()) return InvalidArgument("list_mesh_files", "cannot be combined with validate_only");
      ASSIGN_OR_RETURN(const std::vector<v1::PlanMeshFile> files, PlanMeshFiles(request->spec()));
      for (const v1::PlanMeshFile& file : files) *response->add_mesh_files() = file;
      return Status::Ok();
    }
    ASSIGN_OR_RETURN(ValidatedDataset validated, ValidateDataset(request->spec(), context_, tracker_.catalogue()));
    if (request->validate_only()) return Status::Ok();
    const service::dataset::DatasetPlan& plan = validated.setup->plan;
    const auto total = static_cast<uint32_t>(service::dataset::SceneCount(plan));
    v1::Job* job = response->mutable_job();
    // Held from before the job is recorded until it is queued.
    std::unique_lock<std::mutex> names;
    auto record = [&]() -> StatusOr<std::string> {
      // The resumed job was read before the lock: a delete since then may have taken its directory.
      if (context_.dataset_directories) names = context_.dataset_directories->HoldNames();
      if (const std::string& resumed = request->spec().resume_job_id(); !resumed.empty()) {
        const StatusOr<store::JobRecord> still = tracker_.catalogue().GetJob(resumed);
        if (!still.ok() && still.status().code() == StatusCode::kNotFound) {
          return NotFound("spec.resume_job_id", "no job '" + resumed + "' (deleted meanwhile)");
        }
        RETURN_IF_ERROR(still.status());
      }
      return CreateJob(service::JobKind::kDataset, plan.name, validated.spec, total, job);
    };
    auto run = [this, setup = validated.setup, spec = validated.spec](
                   service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl& control) {
      const service::DatasetJob work{setup, DatasetRootOf(spec, job_id, context_.options),
                                     DatasetDirectoryId(spec, job_id), context_.dataset_directories,
                                     service::DatasetTarBound(context_.options.limits.max_request_memory_bytes)};
      service::RunDatasetJob(recorder, job_id, work, control);
    };
    RETURN_IF_ERROR(Admit("spec", record, std::move(run)));
    spdlog::info("job {}: dataset of {} scenes into {} queued", job->job_id(), total,
                 DatasetRootOf(validated.spec, job->job_id(), context_.options).string());
    return Status::Ok();
  });
}

}  // namespace vscan::api
