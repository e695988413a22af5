// CloudService's unary calls: reads of the catalogue on the callback thread, deletion on the call
// pool.

#include "api/clouds/cloud_service.h"

#include <spdlog/spdlog.h>

#include "api/clouds/cloud_convert.h"
#include "api/transport/unary.h"
#include "api/transport/validate.h"
#include "service/clouds/cloud_store.h"

namespace vscan::api {

grpc::ServerUnaryReactor* CloudService::GetCloud(grpc::CallbackServerContext* ctx, const v1::GetCloudRequest* request,
                                                 v1::GetCloudResponse* response) {
  return RunUnary(ctx, context_.options.token, "GetCloud", [&]() -> Status {
    RETURN_IF_ERROR(RequireId(request->cloud_id(), "cloud_id"));
    ASSIGN_OR_RETURN(const store::CloudRecord cloud, context_.clouds.Get(request->cloud_id()));
    ToProto(cloud, response->mutable_cloud());
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* CloudService::ListClouds(grpc::CallbackServerContext* ctx,
                                                   const v1::ListCloudsRequest* request,
                                                   v1::ListCloudsResponse* response) {
  return RunUnary(ctx, context_.options.token, "ListClouds", [&]() -> Status {
    ASSIGN_OR_RETURN(const int limit, PageSize(request->page_size(), context_.options.limits.max_page_size));
    RETURN_IF_ERROR(CheckPageToken(request->page_token(), "cld_"));
    RETURN_IF_ERROR(CheckText(request->job_id(), "job_id", 64));
    ASSIGN_OR_RETURN(auto clouds, context_.clouds.List(request->page_token(), limit + 1, request->job_id()));
    const bool more = static_cast<int>(clouds.size()) > limit;
    if (more) clouds.resize(limit);
    for (const auto& cloud : clouds) ToProto(cloud, response->add_clouds());
    if (more) response->set_next_page_token(clouds.back().cloud_id);
    return Status::Ok();
  });
}

grpc::ServerUnaryReactor* CloudService::DeleteCloud(grpc::CallbackServerContext* ctx,
                                                    const v1::DeleteCloudRequest* request,
                                                    v1::DeleteCloudResponse* response) {
  return RunBlockingUnary(ctx, context_.options.token, "DeleteCloud", context_.call_workers, [=, this]() -> Status {
    RETURN_IF_ERROR(RequireId(request->cloud_id(), "cloud_id"));
    ASSIGN_OR_RETURN(const store::CollectedBlobs removed, service::DeleteCloud(context_, request->cloud_id()));
    spdlog::info("cloud {}: deleted ({} files, {} bytes freed)", request->cloud_id(), removed.files, removed.bytes);
    response->set_removed_files(removed.files);
    response->set_removed_bytes(removed.bytes);
    return Status::Ok();
  });
}

}  // namespace vscan::api
