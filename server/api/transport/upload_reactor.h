#pragma once
// The skeleton of a client-streaming upload: token check, one read at a time, each message handed
// to Accept, then Complete on a worker thread once the stream ends cleanly.

#include <grpcpp/support/server_callback.h>
#include <spdlog/spdlog.h>

#include "api/server/auth.h"
#include "api/server/call_observer.h"
#include "service/context/service_context.h"
#include "vscan/common/grpc_status.h"

namespace vscan::api {

template <typename Request>
class UploadReactor : public grpc::ServerReadReactor<Request> {
 public:
  void OnReadDone(bool ok) final {
    CallScope scope(ctx_);  // the worker pool carries it into Complete
    if (!ok) {
      if (ctx_->IsCancelled()) {
        this->Finish(grpc::Status(grpc::StatusCode::CANCELLED, "upload cancelled"));
        return;
      }
      const bool posted = context_.workers.Post([this] { End(Complete()); });
      if (!posted) End(Unavailable("server is shutting down"));
      return;
    }
    const Status status = Accept(request_);
    if (!status.ok()) {
      End(status);
      return;
    }
    this->StartRead(&request_);
  }

  void OnDone() final { delete this; }

 protected:
  UploadReactor(grpc::CallbackServerContext* ctx, service::ServiceContext& context, const char* method)
      : context_(context), ctx_(ctx), method_(method) {}
  virtual ~UploadReactor() = default;

  // Call last in the derived constructor: once reading starts, callbacks may come at once.
  void Start() {
    CallScope scope(ctx_);
    const Status auth = CheckToken(*ctx_, context_.options.token);
    if (!auth.ok()) {
      End(auth);
      return;
    }
    this->StartRead(&request_);
  }

  // One message of the stream; an error ends the call with it.
  virtual Status Accept(const Request& request) = 0;
  // The stream ended cleanly: import what was sent and fill the response (on a worker thread).
  virtual Status Complete() = 0;

  service::ServiceContext& context_;

 private:
  void End(const Status& status) {
    if (!status.ok()) spdlog::info("{} -> {}", method_, status.ToString());
    this->Finish(ToGrpc(status));
  }

  grpc::CallbackServerContext* ctx_;
  const char* method_;
  Request request_;
};

}  // namespace vscan::api
