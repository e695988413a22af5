// JobService.ResumeJob: an ended campaign run again as the same job, its stored scans passed over;
// a picking job goes on from the pile its scene holds (picking/picking_job_service.cpp).

#include <memory>

#include <spdlog/spdlog.h>

#include "api/campaign/campaign_spec.h"
#include "api/job/job_convert.h"
#include "api/job/job_service.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "service/campaign/campaign_run.h"
#include "vscan/common/proto_convert.h"

namespace vscan::api {
namespace {

// The scans the job's earlier runs stored, by step, as the runner reports them.
StatusOr<service::StoredCampaignScans> StoredScans(const store::JobRecord& job, const service::CampaignPlan& plan) {
  const auto viewpoints = static_cast<uint32_t>(plan.viewpoints.size());
  service::StoredCampaignScans stored;
  for (const store::ArtifactRecord& artifact : job.artifacts) {
    if (artifact.info.empty()) continue;
    v1::ScanArtifactInfo info;
    const std::string where = "job '" + job.job_id + "': artifact " + artifact.name;
    if (!info.ParseFromString(artifact.info)) return DataLoss(where + ": its scan description does not parse");
    if (info.viewpoint_index() >= viewpoints || info.rotation_index() >= plan.rotations) {
      return DataLoss(where + ": its step lies outside the campaign's plan");
    }
    service::StoredCampaignScan scan;
    service::CampaignStepRecord& record = scan.record;
    record.rotation_index = info.rotation_index();
    record.viewpoint_index = info.viewpoint_index();
    record.step = record.rotation_index * viewpoints + record.viewpoint_index;
    record.table_angle_deg = info.table_angle_deg();
    ASSIGN_OR_RETURN(record.arm.commanded_pose, PoseFromProto(info.commanded_sensor_pose(), where));
    ASSIGN_OR_RETURN(record.arm.achieved_pose, PoseFromProto(info.sensor_pose(), where));
    const auto& commanded = info.commanded_joint_positions();
    const auto& achieved = info.achieved_joint_positions();
    record.arm.commanded = Eigen::Map<const Eigen::VectorXd>(commanded.data(), commanded.size());
    record.arm.achieved = Eigen::Map<const Eigen::VectorXd>(achieved.data(), achieved.size());
    record.points = info.points();
    record.file = artifact.name;
    record.artifact_id = artifact.artifact_id;
    scan.sha256 = artifact.sha256;
    stored[record.step] = std::move(scan);
  }
  return stored;
}

}  // namespace

grpc::ServerUnaryReactor* JobService::ResumeJob(grpc::CallbackServerContext* ctx, const v1::ResumeJobRequest* request,
                                                v1::ResumeJobResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "ResumeJob", context_.call_workers, [=, this]() -> Status {
    const std::string& job_id = request->job_id();
    RETURN_IF_ERROR(RequireId(job_id, "job_id"));
    ASSIGN_OR_RETURN(const store::JobRecord ended, tracker_.catalogue().GetJob(job_id));
    if (ended.kind == service::JobKindName(service::JobKind::kPicking)) return ResumePicking(ended, response);
    const std::string campaign_kind(service::JobKindName(service::JobKind::kCampaign));
    RETURN_IF_ERROR(store::CheckResumable(ended, campaign_kind));
    v1::CampaignSpec spec;
    if (!spec.ParseFromString(ended.spec)) return DataLoss("job '" + job_id + "': its stored spec does not parse");
    // The world may have changed since: a scene or mount deleted meanwhile refuses the resume.
    auto validated = ValidateCampaign(spec, context_, false);
    if (!validated.ok()) {
      return Status(validated.status().code(), "job_id: job '" + job_id + "' cannot run again: " +
                                                   validated.status().ToString());
    }
    auto plan = std::make_shared<const service::CampaignPlan>(std::move(validated).value());
    // The scans the reopen keeps are those the ended job holds with a description.
    ASSIGN_OR_RETURN(service::StoredCampaignScans scans, StoredScans(ended, *plan));
    auto stored = std::make_shared<const service::StoredCampaignScans>(std::move(scans));
    store::JobRecord reopened;
    auto reopen = [&]() -> StatusOr<std::string> {
      ASSIGN_OR_RETURN(reopened, tracker_.Reopen(job_id, campaign_kind));
      return job_id;
    };
    RETURN_IF_ERROR(Admit("job_id", reopen,
                          [this, plan, stored](service::JobRecorder& recorder, const std::string& id,
                                               jobs::JobControl& control) {
                            service::RunCampaign(context_, recorder, id, *plan, control, *stored);
                          }));
    spdlog::info("job {}: campaign resumed, {} of {} scans stored", job_id, stored->size(), plan->steps_total());
    return ToProto(reopened, response->mutable_job());
  });
}

}  // namespace vscan::api
