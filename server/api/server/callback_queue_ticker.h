#pragma once
// Keeps gRPC's callback threads polling. With this gRPC (1.51, epoll) the callback API runs on a
// process-wide completion queue whose threads, after a second without an event, sleep 100 ms
// before they poll again: a call that arrives then waits up to 100 ms before its handler runs,
// which is what the first scan after an idle second paid. A Health check on an in-process
// channel every period (well under a second) gives those threads an event, so they never sleep.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>

#include <grpcpp/channel.h>
#include <grpcpp/server.h>

namespace vscan::api {

// Metadata that marks the ticker's own checks, which the call metrics and logs leave out.
inline constexpr char kTickHeader[] = "x-vscan-tick";

class CallbackQueueTicker {
 public:
  // server must be started, serve grpc.health.v1.Health, and outlive the ticker.
  CallbackQueueTicker(grpc::Server& server, std::chrono::milliseconds period);
  ~CallbackQueueTicker();
  CallbackQueueTicker(const CallbackQueueTicker&) = delete;
  CallbackQueueTicker& operator=(const CallbackQueueTicker&) = delete;

  // Stops ticking (before the server shuts down); idempotent.
  void Stop();
  // Checks answered OK so far.
  uint64_t ticks() const;

 private:
  void Run();
  bool Tick();

  const std::chrono::milliseconds period_;
  std::shared_ptr<grpc::Channel> channel_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  uint64_t ticks_ = 0;
  std::thread thread_;
};

}  // namespace vscan::api
