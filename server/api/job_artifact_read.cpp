// JobService.ReadArtifact: an artifact's bytes in chunks of at most 1 MiB, the first with its metadata.

#include <algorithm>

#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "api/job_convert.h"
#include "api/job_service.h"
#include "api/validate.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {
namespace {

constexpr size_t kChunkBytes = 1u << 20;

// The blob is read on a worker thread; writes then proceed one at a time.
class ReadArtifactReactor final : public grpc::ServerWriteReactor<v1::ReadArtifactResponse> {
 public:
  ReadArtifactReactor(grpc::CallbackServerContext* ctx, const v1::ReadArtifactRequest& request,
                      service::ServiceContext& context, JobTracker& tracker)
      : request_(request), tracker_(tracker) {
    Status status = CheckToken(*ctx, context.options.token);
    if (status.ok()) status = RequireId(request.job_id(), "job_id");
    if (status.ok()) status = RequireId(request.artifact_id(), "artifact_id");
    if (!status.ok()) {
      Fail(status);
      return;
    }
    if (!context.workers.Post([this] { Load(); })) Fail(Unavailable("server is shutting down"));
  }

  void OnWriteDone(bool ok) override {
    if (!ok) {
      Finish(grpc::Status(grpc::StatusCode::CANCELLED, "reader went away"));
      return;
    }
    WriteNext();
  }

  void OnDone() override { delete this; }

 private:
  void Load() {
    auto record = tracker_.catalogue().GetArtifact(request_.job_id(), request_.artifact_id());
    if (!record.ok()) {
      Fail(record.status());
      return;
    }
    auto bytes = tracker_.blobs().Get(record->sha256);
    if (!bytes.ok()) {
      Fail(bytes.status());
      return;
    }
    bytes_ = std::move(bytes).value();
    const Status converted = ToProto(*record, response_.mutable_artifact());
    if (!converted.ok()) {
      Fail(converted);
      return;
    }
    WriteChunk();
  }

  void WriteChunk() {
    const size_t count = std::min(kChunkBytes, bytes_.size() - offset_);
    response_.set_chunk(bytes_.substr(offset_, count));
    offset_ += count;
    StartWrite(&response_);
  }

  void WriteNext() {
    if (offset_ >= bytes_.size()) {
      Finish(grpc::Status::OK);
      return;
    }
    response_.Clear();
    WriteChunk();
  }

  void Fail(const Status& status) {
    spdlog::info("ReadArtifact -> {}", status.ToString());
    Finish(ToGrpc(status));
  }

  const v1::ReadArtifactRequest request_;
  JobTracker& tracker_;
  std::string bytes_;
  size_t offset_ = 0;
  v1::ReadArtifactResponse response_;
};

}  // namespace

grpc::ServerWriteReactor<v1::ReadArtifactResponse>* JobService::ReadArtifact(grpc::CallbackServerContext* ctx,
                                                                             const v1::ReadArtifactRequest* request) {
  return new ReadArtifactReactor(ctx, *request, context_, tracker_);
}

}  // namespace vscan::api
