#pragma once
// One thread that acts on operations that have not completed within a fixed time limit: each
// armed operation either is disarmed in time or has its on_stall run once, on the watchdog's
// thread, without any watchdog lock held (so on_stall may arm and disarm).

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

namespace vscan::guards {

class StallWatchdog {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StallWatchdog(Clock::duration limit);
  ~StallWatchdog();
  StallWatchdog(const StallWatchdog&) = delete;
  StallWatchdog& operator=(const StallWatchdog&) = delete;

  Clock::duration limit() const { return limit_; }
  // Runs on_stall after the limit unless Disarm(id) comes first; the id is never 0.
  uint64_t Arm(std::function<void()> on_stall);
  // Forgets the operation; on_stall may already be running when this returns.
  void Disarm(uint64_t id);
  // Joins the thread; what is still armed never runs.
  void Stop();

 private:
  struct Entry {
    Clock::time_point deadline;
    std::function<void()> on_stall;
  };
  void Run();

  const Clock::duration limit_;
  std::mutex mutex_;
  std::condition_variable wake_;
  // Keyed by arming order, which with one limit for all is also deadline order.
  std::map<uint64_t, Entry> armed_;
  uint64_t next_id_ = 1;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace vscan::guards
