#pragma once
// ScanService: casts a scan on a worker thread and streams it back in chunks.

#include "api/service_context.h"
#include "vscan/v1/scan.grpc.pb.h"

namespace vscan::api {

class ScanService final : public v1::ScanService::CallbackService {
 public:
  explicit ScanService(ServiceContext& context) : context_(context) {}

  grpc::ServerWriteReactor<v1::ScanResponse>* Scan(grpc::CallbackServerContext* ctx,
                                                   const v1::ScanRequest* request) override;
  grpc::ServerUnaryReactor* ListSensorPresets(grpc::CallbackServerContext* ctx,
                                              const v1::ListSensorPresetsRequest* request,
                                              v1::ListSensorPresetsResponse* response) override;

 private:
  ServiceContext& context_;
};

}  // namespace vscan::api
