#pragma once
// Runs a unary handler: token check, the handler, exceptions caught, status mapped to gRPC.

#include <exception>
#include <string>

#include <grpcpp/support/server_callback.h>
#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {

template <typename Handler>
grpc::ServerUnaryReactor* RunUnary(grpc::CallbackServerContext* ctx, const std::string& token, const char* method,
                                   Handler&& handler) {
  auto* reactor = ctx->DefaultReactor();
  Status status = CheckToken(*ctx, token);
  if (status.ok()) {
    try {
      status = handler();
    } catch (const std::exception& e) {
      status = Internal(std::string("unexpected error: ") + e.what());
    }
  }
  if (!status.ok()) spdlog::info("{} -> {}", method, status.ToString());
  reactor->Finish(ToGrpc(status));
  return reactor;
}

}  // namespace vscan::api
