#pragma once
// ScanService: casts a scan on a worker thread and streams it back in chunks.

#include "guards/stall_watchdog.h"
#include "service/context/service_context.h"
#include "vscan/v1/scan.grpc.pb.h"

namespace vscan::api {

class ScanService final : public v1::ScanService::CallbackService {
 public:
  // stalled_readers cancels streams whose client stopped reading; null watches nothing.
  ScanService(service::ServiceContext& context, guards::StallWatchdog* stalled_readers)
      : context_(context), stalled_readers_(stalled_readers) {}

  grpc::ServerWriteReactor<v1::ScanResponse>* Scan(grpc::CallbackServerContext* ctx,
                                                   const v1::ScanRequest* request) override;
  grpc::ServerUnaryReactor* ListSensorPresets(grpc::CallbackServerContext* ctx,
                                              const v1::ListSensorPresetsRequest* request,
                                              v1::ListSensorPresetsResponse* response) override;

 private:
  service::ServiceContext& context_;
  guards::StallWatchdog* stalled_readers_;
};

}  // namespace vscan::api
