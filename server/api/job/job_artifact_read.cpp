// JobService.ReadArtifact: an artifact's bytes in chunks of at most 1 MiB, the first with its metadata.

#include "api/server/auth.h"
#include "api/transport/blob_stream_reactor.h"
#include "api/server/call_observer.h"
#include "api/job/job_convert.h"
#include "api/job/job_service.h"
#include "api/transport/validate.h"

namespace vscan::api {

grpc::ServerWriteReactor<v1::ReadArtifactResponse>* JobService::ReadArtifact(grpc::CallbackServerContext* ctx,
                                                                             const v1::ReadArtifactRequest* request) {
  CallScope scope(ctx);
  Status checked = CheckToken(*ctx, context_.options.token);
  if (checked.ok()) checked = RequireId(request->job_id(), "job_id");
  if (checked.ok()) checked = RequireId(request->artifact_id(), "artifact_id");
  auto open = [this, job_id = request->job_id(), artifact_id = request->artifact_id()](
                  v1::ReadArtifactResponse* first) -> StatusOr<store::BlobReader> {
    ASSIGN_OR_RETURN(const store::ArtifactRecord record, tracker_.catalogue().GetArtifact(job_id, artifact_id));
    RETURN_IF_ERROR(ToProto(record, first->mutable_artifact()));
    return tracker_.blobs().OpenReader(record.sha256);
  };
  return new BlobStreamReactor<v1::ReadArtifactResponse>(checked, "ReadArtifact", ctx, context_.workers,
                                                         stalled_readers_, std::move(open));
}

}  // namespace vscan::api
