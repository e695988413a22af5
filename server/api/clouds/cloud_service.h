#pragma once
// CloudService: stored point clouds, uploaded by clients or captured by campaigns.

#include "guards/stall_watchdog.h"
#include "service/context/service_context.h"
#include "vscan/v1/cloud.grpc.pb.h"

namespace vscan::api {

class CloudService final : public v1::CloudService::CallbackService {
 public:
  // stalled_readers cancels ReadCloud streams whose client stopped reading; null watches nothing.
  CloudService(service::ServiceContext& context, guards::StallWatchdog* stalled_readers)
      : context_(context), stalled_readers_(stalled_readers) {}

  grpc::ServerReadReactor<v1::UploadCloudRequest>* UploadCloud(grpc::CallbackServerContext* ctx,
                                                               v1::UploadCloudResponse* response) override;
  grpc::ServerUnaryReactor* GetCloud(grpc::CallbackServerContext* ctx, const v1::GetCloudRequest* request,
                                     v1::GetCloudResponse* response) override;
  grpc::ServerUnaryReactor* ListClouds(grpc::CallbackServerContext* ctx, const v1::ListCloudsRequest* request,
                                       v1::ListCloudsResponse* response) override;
  grpc::ServerUnaryReactor* DeleteCloud(grpc::CallbackServerContext* ctx, const v1::DeleteCloudRequest* request,
                                        v1::DeleteCloudResponse* response) override;
  grpc::ServerWriteReactor<v1::ReadCloudResponse>* ReadCloud(grpc::CallbackServerContext* ctx,
                                                             const v1::ReadCloudRequest* request) override;

 private:
  service::ServiceContext& context_;
  guards::StallWatchdog* stalled_readers_;
};

}  // namespace vscan::api
