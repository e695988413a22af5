#pragma once
// A blocking unary call that stops when its client cancels or its deadline passes: the handler
// runs on a worker pool with a flag that the call's OnCancel sets (gRPC also cancels a call whose
// deadline passes, and every call still running when the server's grace period ends).

#include <atomic>
#include <memory>

#include <grpcpp/support/server_callback.h>

#include "api/transport/unary.h"

namespace vscan::api {

class CancellableUnaryReactor final : public grpc::ServerUnaryReactor {
 public:
  std::shared_ptr<const std::atomic<bool>> cancel() const { return cancel_; }
  void OnCancel() override { cancel_->store(true); }
  void OnDone() override { delete this; }

 private:
  std::shared_ptr<std::atomic<bool>> cancel_ = std::make_shared<std::atomic<bool>>(false);
};

// Handler: Status(const std::atomic<bool>& cancel), copied onto the pool (capture the request and
// response pointers by value).
template <typename Handler>
grpc::ServerUnaryReactor* RunCancellableUnary(grpc::CallbackServerContext* ctx, const std::string& token,
                                              const char* method, jobs::WorkerPool& workers, Handler handler) {
  CallScope scope(ctx);  // the pool carries it onto the worker
  auto* reactor = new CancellableUnaryReactor();
  const Status status = CheckToken(*ctx, token);
  if (!status.ok()) {
    FinishUnary(reactor, method, status);
    return reactor;
  }
  const bool posted = workers.Post([reactor, method, handler, cancel = reactor->cancel()]() mutable {
    auto call = [&handler, &cancel] { return handler(*cancel); };
    FinishUnary(reactor, method, InvokeHandler(call));
  });
  if (!posted) FinishUnary(reactor, method, Unavailable("server is shutting down"));
  return reactor;
}

}  // namespace vscan::api
