#include "jobs/job_runner.h"

#include <algorithm>

#include "observability/request_id.h"

namespace vscan::jobs {

void JobControl::RequestStop(StopReason reason) {
  StopReason none = StopReason::kNone;
  reason_.compare_exchange_strong(none, reason);
  flag_.store(true);
}

JobRunner::JobRunner(size_t max_concurrent) {
  const size_t threads = std::max<size_t>(1, max_concurrent);
  threads_.reserve(threads);
  for (size_t i = 0; i < threads; ++i) threads_.emplace_back([this] { Run(); });
}

JobRunner::~JobRunner() { Stop(); }

bool JobRunner::Submit(const std::string& job_id, Work work, Dropped dropped, size_t max_queued) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ || queue_.size() >= max_queued) return false;
    // A job logs under the request id of the call that started it.
    queue_.push_back({job_id, observability::CarryRequestId(std::move(work)), std::move(dropped)});
  }
  wake_.notify_one();
  return true;
}

JobRunner::CancelOutcome JobRunner::Cancel(const std::string& job_id) {
  Dropped dropped;
  {
    std::lock_guard lock(mutex_);
    // The queue first: a resumed job may wait there while its earlier run's thread still returns.
    auto it = std::find_if(queue_.begin(), queue_.end(), [&](const Entry& e) { return e.job_id == job_id; });
    if (it == queue_.end()) {
      auto running = running_.find(job_id);
      if (running == running_.end()) return CancelOutcome::kUnknown;
      running->second->RequestStop(StopReason::kCancelled);
      return CancelOutcome::kSignalled;
    }
    dropped = std::move(it->dropped);
    queue_.erase(it);
  }
  if (dropped) dropped(StopReason::kCancelled);
  return CancelOutcome::kDequeued;
}

void JobRunner::Stop() {
  std::deque<Entry> dropped;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && threads_.empty()) return;
    stopping_ = true;
    dropped.swap(queue_);
    for (auto& [id, control] : running_) control->RequestStop(StopReason::kShutdown);
  }
  wake_.notify_all();
  for (Entry& entry : dropped) {
    if (entry.dropped) entry.dropped(StopReason::kShutdown);
  }
  for (auto& t : threads_) {
    if (t.joinable()) t.join();
  }
  std::lock_guard lock(mutex_);
  threads_.clear();
}

size_t JobRunner::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

size_t JobRunner::running() const {
  std::lock_guard lock(mutex_);
  return running_.size();
}

void JobRunner::Run() {
  for (;;) {
    Entry entry;
    auto control = std::make_shared<JobControl>();
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      entry = std::move(queue_.front());
      queue_.pop_front();
      running_[entry.job_id] = control;
    }
    entry.work(*control);
    std::lock_guard lock(mutex_);
    // A resumed job of the same id may run on another thread by now.
    if (auto it = running_.find(entry.job_id); it != running_.end() && it->second == control) running_.erase(it);
  }
}

}  // namespace vscan::jobs
