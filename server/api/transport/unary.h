#pragma once
// Runs a unary handler: token check, the handler, exceptions caught, status mapped to gRPC; on the
// gRPC callback thread, or on a worker pool for work that blocks.

#include <exception>
#include <string>

#include <grpcpp/support/server_callback.h>
#include <spdlog/spdlog.h>

#include "api/server/auth.h"
#include "api/server/call_observer.h"
#include "jobs/worker_pool.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {

template <typename Handler>
Status InvokeHandler(Handler& handler) {
  try {
    return handler();
  } catch (const std::exception& e) {
    return Internal(std::string("unexpected error: ") + e.what());
  }
}

inline void FinishUnary(grpc::ServerUnaryReactor* reactor, const char* method, const Status& status) {
  if (!status.ok()) spdlog::info("{} -> {}", method, status.ToString());
  reactor->Finish(ToGrpc(status));
}

// For handlers that only read memory or the catalogue: they run on the callback thread.
template <typename Handler>
grpc::ServerUnaryReactor* RunUnary(grpc::CallbackServerContext* ctx, const std::string& token, const char* method,
                                   Handler&& handler) {
  CallScope scope(ctx);
  auto* reactor = ctx->DefaultReactor();
  Status status = CheckToken(*ctx, token);
  if (status.ok()) status = InvokeHandler(handler);
  FinishUnary(reactor, method, status);
  return reactor;
}

// For handlers that block (synchronous SQLite writes, inverse kinematics with collision retries):
// they run on workers and the callback thread returns at once. The handler is copied onto the
// pool, so it must capture the request and response pointers by value, not by reference.
template <typename Handler>
grpc::ServerUnaryReactor* RunBlockingUnary(grpc::CallbackServerContext* ctx, const std::string& token,
                                           const char* method, jobs::WorkerPool& workers, Handler handler) {
  CallScope scope(ctx);  // the pool carries it onto the worker
  auto* reactor = ctx->DefaultReactor();
  const Status status = CheckToken(*ctx, token);
  if (!status.ok()) {
    FinishUnary(reactor, method, status);
    return reactor;
  }
  const bool posted = workers.Post([reactor, method, handler]() mutable {
    FinishUnary(reactor, method, InvokeHandler(handler));
  });
  if (!posted) FinishUnary(reactor, method, Unavailable("server is shutting down"));
  return reactor;
}

}  // namespace vscan::api
