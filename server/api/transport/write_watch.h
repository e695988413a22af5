#pragma once
// Cancels a server-streaming call whose write has waited on its client for longer than the
// watchdog's limit: a write completes only when the client reads, so a client that stops reading
// would otherwise hold the call, its slot and its memory for as long as it likes.

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <grpcpp/server_context.h>
#include <spdlog/spdlog.h>

#include "guards/stall_watchdog.h"

namespace vscan::api {

class WriteWatch {
 public:
  // A null watchdog watches nothing.
  WriteWatch(guards::StallWatchdog* watchdog, grpc::CallbackServerContext* ctx)
      : watchdog_(watchdog), call_(std::make_shared<Call>()) {
    call_->ctx = ctx;
  }
  ~WriteWatch() { Release(); }
  WriteWatch(const WriteWatch&) = delete;
  WriteWatch& operator=(const WriteWatch&) = delete;

  // Before each StartWrite; `what` names the call in the log.
  void Started(const std::string& what) {
    if (watchdog_ == nullptr) return;
    const double seconds = std::chrono::duration<double>(watchdog_->limit()).count();
    armed_ = watchdog_->Arm([call = call_, what, seconds] {
      std::lock_guard lock(call->mutex);
      if (call->ctx == nullptr) return;
      spdlog::warn("{}: the client has not read for {:.1f} s; cancelling the call", what, seconds);
      call->ctx->TryCancel();
    });
  }
  // First thing in OnWriteDone.
  void Done() {
    if (watchdog_ != nullptr && armed_ != 0) watchdog_->Disarm(armed_);
    armed_ = 0;
  }
  // In OnDone: the context is never touched after this returns.
  void Release() {
    Done();
    std::lock_guard lock(call_->mutex);
    call_->ctx = nullptr;
  }

 private:
  struct Call {
    // Recursive: TryCancel may run the reactor's OnWriteDone and OnDone on the calling thread.
    std::recursive_mutex mutex;
    grpc::CallbackServerContext* ctx = nullptr;
  };

  guards::StallWatchdog* watchdog_;
  std::shared_ptr<Call> call_;
  uint64_t armed_ = 0;
};

}  // namespace vscan::api
