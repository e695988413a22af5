#pragma once
// LocalizationService: the baseline localizer on stored or sent points, and BOP scoring of poses.

#include "service/context/service_context.h"
#include "vscan/v1/localization.grpc.pb.h"

namespace vscan::api {

class LocalizationService final : public v1::LocalizationService::CallbackService {
 public:
  explicit LocalizationService(service::ServiceContext& context) : context_(context) {}

  grpc::ServerUnaryReactor* Localize(grpc::CallbackServerContext* ctx, const v1::LocalizeRequest* request,
                                     v1::LocalizeResponse* response) override;
  grpc::ServerUnaryReactor* ScorePoses(grpc::CallbackServerContext* ctx, const v1::ScorePosesRequest* request,
                                       v1::ScorePosesResponse* response) override;

 private:
  service::ServiceContext& context_;
};

}  // namespace vscan::api
