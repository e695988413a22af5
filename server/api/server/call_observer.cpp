#include "api/server/call_observer.h"

#include <chrono>
#include <mutex>
#include <unordered_map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "api/server/callback_queue_ticker.h"
#include "observability/log_fields.h"
#include "observability/server_metrics.h"

namespace vscan::api {
namespace {

using grpc::experimental::InterceptionHookPoints;
using Clock = std::chrono::steady_clock;

// The request id of each call in progress, for handlers that only hold its context.
class CallIds {
 public:
  void Set(const grpc::ServerContextBase* ctx, const std::string& id) {
    std::lock_guard lock(mutex_);
    ids_[ctx] = id;
  }
  void Erase(const grpc::ServerContextBase* ctx) {
    std::lock_guard lock(mutex_);
    ids_.erase(ctx);
  }
  std::string Get(const grpc::ServerContextBase* ctx) const {
    std::lock_guard lock(mutex_);
    const auto it = ids_.find(ctx);
    return it == ids_.end() ? std::string() : it->second;
  }

 private:
  mutable std::mutex mutex_;
  std::unordered_map<const grpc::ServerContextBase*, std::string> ids_;
};

CallIds& Ids() {
  static CallIds ids;
  return ids;
}

const char* CodeName(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return "OK";
    case grpc::StatusCode::CANCELLED: return "CANCELLED";
    case grpc::StatusCode::UNKNOWN: return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT: return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED: return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND: return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS: return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED: return "PERMISSION_DENIED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION: return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED: return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE: return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED: return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL: return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE: return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS: return "DATA_LOSS";
    case grpc::StatusCode::UNAUTHENTICATED: return "UNAUTHENTICATED";
    default: return "UNKNOWN";
  }
}

class CallObserver final : public grpc::experimental::Interceptor {
 public:
  explicit CallObserver(grpc::experimental::ServerRpcInfo* info)
      : method_(info->method()), ctx_(info->server_context()) {}

  ~CallObserver() override {
    if (!observed_) return;
    // A call torn down without a status sent (its client went away) counts as cancelled.
    if (!recorded_) Record(grpc::StatusCode::CANCELLED);
    Ids().Erase(ctx_);
  }

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_INITIAL_METADATA)) {
      const auto& metadata = *methods->GetRecvInitialMetadata();
      // The server's own ticks would swamp the counts and the debug log four times a second.
      observed_ = metadata.find(kTickHeader) == metadata.end();
      start_ = Clock::now();
      request_id_ = ClientRequestId(metadata);
      if (request_id_.empty()) request_id_ = observability::NewRequestId();
      if (observed_) Ids().Set(ctx_, request_id_);
    }
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      methods->GetSendInitialMetadata()->emplace(kRequestIdHeader, request_id_);
    }
    if (observed_ && !recorded_ && methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS)) {
      Record(methods->GetSendStatus().error_code());
    }
    methods->Proceed();
  }

 private:
  static std::string ClientRequestId(const std::multimap<grpc::string_ref, grpc::string_ref>& metadata) {
    const auto it = metadata.find(kRequestIdHeader);
    if (it == metadata.end()) return {};
    std::string id(it->second.data(), it->second.size());
    return observability::IsSaneRequestId(id) ? id : std::string();
  }

  void Record(grpc::StatusCode code) {
    recorded_ = true;
    const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
    const std::string code_name = CodeName(code);
    auto& metrics = observability::Metrics();
    metrics.grpc_calls.WithLabels({method_, code_name}).Increment();
    if (code != grpc::StatusCode::OK) metrics.grpc_errors.WithLabels({method_, code_name}).Increment();
    metrics.grpc_duration.WithLabels({method_}).Observe(seconds);
    if (spdlog::should_log(spdlog::level::debug)) {
      observability::RequestIdScope scope(request_id_);
      observability::LogFieldsScope fields({{"method", method_},
                                            {"code", code_name},
                                            {"duration_ms", fmt::format("{:.3f}", seconds * 1e3), true}});
      spdlog::debug("call ended");  // the method, code and duration are fields
    }
  }

  const std::string method_;
  const grpc::ServerContextBase* const ctx_;
  bool observed_ = false;
  bool recorded_ = false;
  Clock::time_point start_;
  std::string request_id_;
};

class CallObserverFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override {
    return new CallObserver(info);
  }
};

}  // namespace

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> MakeCallObserverFactory() {
  return std::make_unique<CallObserverFactory>();
}

std::string RequestIdOf(const grpc::ServerContextBase* ctx) { return Ids().Get(ctx); }

}  // namespace vscan::api
