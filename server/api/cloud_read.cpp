// CloudService.ReadCloud: a cloud's binary PLY in chunks of at most 1 MiB, the first with its
// metadata.

#include "api/auth.h"
#include "api/blob_stream_reactor.h"
#include "api/call_observer.h"
#include "api/cloud_convert.h"
#include "api/cloud_service.h"
#include "api/validate.h"
#include "service/cloud_store.h"

namespace vscan::api {

grpc::ServerWriteReactor<v1::ReadCloudResponse>* CloudService::ReadCloud(grpc::CallbackServerContext* ctx,
                                                                         const v1::ReadCloudRequest* request) {
  CallScope scope(ctx);
  Status checked = CheckToken(*ctx, context_.options.token);
  if (checked.ok()) checked = RequireId(request->cloud_id(), "cloud_id");
  auto load = [this, cloud_id = request->cloud_id()](std::string* bytes, v1::ReadCloudResponse* first) -> Status {
    ASSIGN_OR_RETURN(service::StoredCloud stored, service::LoadCloud(context_, cloud_id));
    ToProto(stored.record, first->mutable_cloud());
    *bytes = std::move(stored.ply);
    return Status::Ok();
  };
  return new BlobStreamReactor<v1::ReadCloudResponse>(checked, "ReadCloud", context_.workers, std::move(load));
}

}  // namespace vscan::api
