#include "guards/stall_watchdog.h"

#include <utility>
#include <vector>

namespace vscan::guards {

StallWatchdog::StallWatchdog(Clock::duration limit) : limit_(limit), thread_([this] { Run(); }) {}

StallWatchdog::~StallWatchdog() { Stop(); }

uint64_t StallWatchdog::Arm(std::function<void()> on_stall) {
  std::lock_guard lock(mutex_);
  const uint64_t id = next_id_++;
  // The clock is read under the lock so that ids and deadlines keep the same order.
  armed_.emplace(id, Entry{Clock::now() + limit_, std::move(on_stall)});
  if (armed_.size() == 1) wake_.notify_one();
  return id;
}

void StallWatchdog::Disarm(uint64_t id) {
  std::function<void()> dropped;  // destroyed outside the lock: it may own what calls Disarm
  std::lock_guard lock(mutex_);
  auto it = armed_.find(id);
  if (it == armed_.end()) return;
  dropped = std::move(it->second.on_stall);
  armed_.erase(it);
}

void StallWatchdog::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::map<uint64_t, Entry> dropped;
  std::lock_guard lock(mutex_);
  dropped.swap(armed_);
}

void StallWatchdog::Run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (armed_.empty()) {
      wake_.wait(lock);
      continue;
    }
    const Clock::time_point first = armed_.begin()->second.deadline;
    if (Clock::now() < first) {
      wake_.wait_until(lock, first);
      continue;
    }
    std::vector<std::function<void()>> due;
    const Clock::time_point now = Clock::now();
    while (!armed_.empty() && armed_.begin()->second.deadline <= now) {
      due.push_back(std::move(armed_.begin()->second.on_stall));
      armed_.erase(armed_.begin());
    }
    lock.unlock();
    for (auto& on_stall : due) on_stall();
    due.clear();
    lock.lock();
  }
}

}  // namespace vscan::guards
