#pragma once
// LocalizationService: the baseline localizer on stored or sent points, and BOP scoring of poses.

#include "guards/stall_watchdog.h"
#include "service/context/service_context.h"
#include "vscan/v1/localization.grpc.pb.h"

namespace vscan::api {

class LocalizationService final : public v1::LocalizationService::CallbackService {
 public:
  // stalled_readers cancels LocalizeWithProgress streams whose client stopped reading; null
  // watches nothing.
  LocalizationService(service::ServiceContext& context, guards::StallWatchdog* stalled_readers)
      : context_(context), stalled_readers_(stalled_readers) {}

  grpc::ServerUnaryReactor* Localize(grpc::CallbackServerContext* ctx, const v1::LocalizeRequest* request,
                                     v1::LocalizeResponse* response) override;
  grpc::ServerWriteReactor<v1::LocalizeWithProgressResponse>* LocalizeWithProgress(
      grpc::CallbackServerContext* ctx, const v1::LocalizeWithProgressRequest* request) override;
  grpc::ServerUnaryReactor* ScorePoses(grpc::CallbackServerContext* ctx, const v1::ScorePosesRequest* request,
                                       v1::ScorePosesResponse* response) override;

 private:
  service::ServiceContext& context_;
  guards::StallWatchdog* stalled_readers_;
};

}  // namespace vscan::api
