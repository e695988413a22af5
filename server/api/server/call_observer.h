#pragma once
// Observes every gRPC call: gives it a request id (the client's x-request-id when sane, else a
// fresh one) that goes back in the response's initial metadata, and records its duration and
// status code in the server metrics.

#include <memory>
#include <string>

#include <grpcpp/support/server_interceptor.h>

#include "observability/request_id.h"

namespace vscan::api {

inline constexpr char kRequestIdHeader[] = "x-request-id";

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> MakeCallObserverFactory();

// The request id of a call in progress; empty for a context the observer has not seen.
std::string RequestIdOf(const grpc::ServerContextBase* ctx);

// Logs of the current thread name the call's request id for the scope's lifetime.
class CallScope {
 public:
  explicit CallScope(const grpc::ServerContextBase* ctx) : scope_(RequestIdOf(ctx)) {}

 private:
  observability::RequestIdScope scope_;
};

}  // namespace vscan::api
