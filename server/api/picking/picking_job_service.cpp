// JobService.StartPicking: a picking job over a succeeded bin fill's scene.

#include <spdlog/spdlog.h>

#include "api/job/job_convert.h"
#include "api/job/job_service.h"
#include "api/picking/picking_estimates_files.h"
#include "api/picking/picking_spec.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "service/picking/picking_run.h"

namespace vscan::api {

grpc::ServerUnaryReactor* JobService::StartPicking(grpc::CallbackServerContext* ctx,
                                                   const v1::StartPickingRequest* request,
                                                   v1::StartPickingResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "StartPicking", context_.call_workers, [=, this]() -> Status {
    if (!request->has_spec()) return InvalidArgument("spec: required");
    const v1::PickingSpec& spec = request->spec();
    RETURN_IF_ERROR(RequireId(spec.bin_job_id(), "spec.bin_job_id"));
    auto bin_job = tracker_.catalogue().GetJob(spec.bin_job_id());
    if (!bin_job.ok()) return Status(bin_job.status().code(), "spec.bin_job_id: " + bin_job.status().message());
    ASSIGN_OR_RETURN(service::PickingPlan validated, ValidatePicking(spec, *bin_job, context_));
    if (request->validate_only()) return Status::Ok();
    auto plan = std::make_shared<const service::PickingPlan>(std::move(validated));
    v1::Job* job = response->mutable_job();
    const auto total = static_cast<uint32_t>(plan->bin.parts_total());
    RETURN_IF_ERROR(Admit(
        "spec", [&] { return CreateJob(service::JobKind::kPicking, spec.name(), spec, total, job); },
        PickingRun(plan, spec.name(), spec.bin_job_id())));
    spdlog::info("job {}: picking in scene {} with mount {} queued", job->job_id(), plan->scene_id, plan->mount_id);
    return Status::Ok();
  });
}

JobService::PickingJobRun JobService::PickingRun(std::shared_ptr<const service::PickingPlan> plan, std::string name,
                                          std::string bin_job_id) {
  return [this, plan, name = std::move(name), bin_job_id = std::move(bin_job_id)](
             service::JobRecorder& recorder, const std::string& job_id, jobs::JobControl& control) {
    if (plan->perception != service::Perception::kClient) {
      service::RunPicking(context_, recorder, job_id, name, bin_job_id, *plan, control);
      return;
    }
    const service::ClientEstimates client = ClientEstimatesOver(
        std::make_shared<const PickingEstimatesFiles>(context_.options.data_dir, job_id), picking_estimates_);
    service::RunPicking(context_, recorder, job_id, name, bin_job_id, *plan, control, &client);
  };
}

Status JobService::ResumePicking(const store::JobRecord& ended, v1::ResumeJobResponse* response) {
  const std::string kind(service::JobKindName(service::JobKind::kPicking));
  RETURN_IF_ERROR(store::CheckResumable(ended, kind));
  v1::PickingSpec spec;
  if (!spec.ParseFromString(ended.spec)) return DataLoss("job '" + ended.job_id + "': its stored spec does not parse");
  auto bin_job = tracker_.catalogue().GetJob(spec.bin_job_id());
  auto validated = bin_job.ok() ? ValidatePicking(spec, *bin_job, context_)
                                : StatusOr<service::PickingPlan>(bin_job.status());
  if (!validated.ok()) {
    return Status(validated.status().code(), "job_id: job '" + ended.job_id + "' cannot run again: " +
                                                 validated.status().ToString());
  }
  auto plan = std::make_shared<const service::PickingPlan>(std::move(validated).value());
  store::JobRecord reopened;
  auto reopen = [&]() -> StatusOr<std::string> {
    ASSIGN_OR_RETURN(reopened, tracker_.Reopen(ended.job_id, kind));
    return ended.job_id;
  };
  RETURN_IF_ERROR(Admit("job_id", reopen, PickingRun(plan, spec.name(), spec.bin_job_id())));
  spdlog::info("job {}: picking resumed on scene {}", ended.job_id, plan->scene_id);
  return ToProto(reopened, response->mutable_job());
}

}  // namespace vscan::api
