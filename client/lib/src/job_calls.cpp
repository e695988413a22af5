// Client's JobService calls: scan campaigns, model jobs, their events and their artifacts.

#include "byte_streams.h"
#include "paging.h"
#include "unary_call.h"
#include "vscan/v1/job.grpc.pb.h"

namespace vscan::client {
namespace {

using JobStub = v1::JobService::Stub;

std::unique_ptr<JobStub> NewJobStub(const Client& client) { return v1::JobService::NewStub(client.channel()); }

}  // namespace

StatusOr<v1::Job> Client::StartCampaign(const v1::CampaignSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartCampaignRequest request;
  *request.mutable_spec() = spec;
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::StartCampaign, request));
  return response.job();
}

Status Client::ValidateCampaign(const v1::CampaignSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartCampaignRequest request;
  *request.mutable_spec() = spec;
  request.set_validate_only(true);
  return UnaryCall(*this, *stub, &JobStub::StartCampaign, request).status();
}

StatusOr<v1::Job> Client::StartModel(const v1::ModelSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartModelRequest request;
  *request.mutable_spec() = spec;
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::StartModel, request));
  return response.job();
}

Status Client::ValidateModel(const v1::ModelSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartModelRequest request;
  *request.mutable_spec() = spec;
  request.set_validate_only(true);
  return UnaryCall(*this, *stub, &JobStub::StartModel, request).status();
}

StatusOr<v1::Job> Client::StartBinFill(const v1::BinFillSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartBinFillRequest request;
  *request.mutable_spec() = spec;
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::StartBinFill, request));
  return response.job();
}

Status Client::ValidateBinFill(const v1::BinFillSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartBinFillRequest request;
  *request.mutable_spec() = spec;
  request.set_validate_only(true);
  return UnaryCall(*this, *stub, &JobStub::StartBinFill, request).status();
}

StatusOr<v1::Job> Client::StartPicking(const v1::PickingSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartPickingRequest request;
  *request.mutable_spec() = spec;
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::StartPicking, request));
  return response.job();
}

Status Client::ValidatePicking(const v1::PickingSpec& spec) {
  auto stub = NewJobStub(*this);
  v1::StartPickingRequest request;
  *request.mutable_spec() = spec;
  request.set_validate_only(true);
  return UnaryCall(*this, *stub, &JobStub::StartPicking, request).status();
}

StatusOr<uint32_t> Client::SubmitPickingEstimates(const v1::SubmitPickingEstimatesRequest& request) {
  auto stub = NewJobStub(*this);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::SubmitPickingEstimates, request));
  return response.accepted();
}

StatusOr<v1::Job> Client::GetJob(const std::string& job_id) {
  auto stub = NewJobStub(*this);
  v1::GetJobRequest request;
  request.set_job_id(job_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::GetJob, request));
  return response.job();
}

StatusOr<std::vector<v1::Job>> Client::ListJobs() {
  auto stub = NewJobStub(*this);
  return CollectPages<v1::Job>(
      [&](const std::string& token) {
        v1::ListJobsRequest request;
        request.set_page_token(token);
        return UnaryCall(*this, *stub, &JobStub::ListJobs, request);
      },
      [](const v1::ListJobsResponse& page) { return page.jobs(); });
}

StatusOr<v1::Job> Client::CancelJob(const std::string& job_id) {
  auto stub = NewJobStub(*this);
  v1::CancelJobRequest request;
  request.set_job_id(job_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::CancelJob, request));
  return response.job();
}

StatusOr<v1::Job> Client::ResumeJob(const std::string& job_id) {
  auto stub = NewJobStub(*this);
  v1::ResumeJobRequest request;
  request.set_job_id(job_id);
  ASSIGN_OR_RETURN(auto response, UnaryCall(*this, *stub, &JobStub::ResumeJob, request));
  return response.job();
}

StatusOr<v1::DeleteJobResponse> Client::DeleteJob(const std::string& job_id) {
  auto stub = NewJobStub(*this);
  v1::DeleteJobRequest request;
  request.set_job_id(job_id);
  return UnaryCall(*this, *stub, &JobStub::DeleteJob, request);
}

Status Client::WatchJob(const std::string& job_id, const JobEventFn& on_event) {
  auto stub = NewJobStub(*this);
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  v1::WatchJobRequest request;
  request.set_job_id(job_id);
  auto reader = stub->WatchJob(&context, request);
  v1::WatchJobResponse response;
  bool stopped = false;
  while (reader->Read(&response)) {
    if (on_event && !on_event(response)) {
      stopped = true;
      context.TryCancel();
      break;
    }
  }
  const grpc::Status status = reader->Finish();
  if (stopped && status.error_code() == grpc::StatusCode::CANCELLED) return Status::Ok();
  return FromGrpc(status);
}

StatusOr<v1::Artifact> Client::ReadArtifact(const std::string& job_id, const std::string& artifact_id,
                                            const ArtifactSink& sink, const ProgressFn& progress) {
  auto stub = NewJobStub(*this);
  grpc::ClientContext context;
  PrepareContext(&context, options_.stream_timeout);
  v1::ReadArtifactRequest request;
  request.set_job_id(job_id);
  request.set_artifact_id(artifact_id);
  auto reader = stub->ReadArtifact(&context, request);
  return ReceiveChunks<v1::ReadArtifactResponse, v1::Artifact>(
      context, *reader, [](const v1::ReadArtifactResponse& r) { return r.artifact(); },
      [](const v1::Artifact& a) { return a.size_bytes(); }, sink, progress, "artifact '" + artifact_id + "'");
}

}  // namespace vscan::client
