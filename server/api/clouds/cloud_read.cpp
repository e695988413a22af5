// CloudService.ReadCloud: a cloud's binary PLY in chunks of at most 1 MiB, the first with its
// metadata.

#include "api/server/auth.h"
#include "api/transport/blob_stream_reactor.h"
#include "api/server/call_observer.h"
#include "api/clouds/cloud_convert.h"
#include "api/clouds/cloud_service.h"
#include "api/transport/validate.h"

namespace vscan::api {

grpc::ServerWriteReactor<v1::ReadCloudResponse>* CloudService::ReadCloud(grpc::CallbackServerContext* ctx,
                                                                         const v1::ReadCloudRequest* request) {
  CallScope scope(ctx);
  Status checked = CheckToken(*ctx, context_.options.token);
  if (checked.ok()) checked = RequireId(request->cloud_id(), "cloud_id");
  auto open = [this, cloud_id = request->cloud_id()](v1::ReadCloudResponse* first) -> StatusOr<store::BlobReader> {
    ASSIGN_OR_RETURN(const store::CloudRecord record, context_.clouds.Get(cloud_id));
    ToProto(record, first->mutable_cloud());
    return context_.blobs.OpenReader(record.sha256);
  };
  return new BlobStreamReactor<v1::ReadCloudResponse>(checked, "ReadCloud", ctx, context_.workers, stalled_readers_,
                                                      std::move(open));
}

}  // namespace vscan::api
