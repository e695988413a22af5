#pragma once
// PickingService: grasps of stored meshes, and which parts of a scene a mounted robot can pick.

#include "service/context/service_context.h"
#include "vscan/v1/picking.grpc.pb.h"

namespace vscan::api {

class PickingService final : public v1::PickingService::CallbackService {
 public:
  explicit PickingService(service::ServiceContext& context) : context_(context) {}

  grpc::ServerUnaryReactor* GenerateGrasps(grpc::CallbackServerContext* ctx, const v1::GenerateGraspsRequest* request,
                                           v1::GenerateGraspsResponse* response) override;
  grpc::ServerUnaryReactor* CheckPicks(grpc::CallbackServerContext* ctx, const v1::CheckPicksRequest* request,
                                       v1::CheckPicksResponse* response) override;

 private:
  service::ServiceContext& context_;
};

}  // namespace vscan::api
