#pragma once
// Runs long jobs on a few dedicated threads: at most max_concurrent at once, the rest wait in
// submission order. Each job gets a cancel flag it checks between units of work.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vscan::jobs {

// Why a job was asked to stop.
enum class StopReason { kNone, kCancelled, kShutdown };

// Shared by the runner and the job's work: the job polls stop_requested() between steps.
class JobControl {
 public:
  bool stop_requested() const { return flag_.load(); }
  StopReason reason() const { return reason_.load(); }
  // The flag to hand to code that polls a plain atomic (e.g. a scan in progress).
  const std::atomic<bool>* flag() const { return &flag_; }
  // The first reason given wins.
  void RequestStop(StopReason reason);

 private:
  std::atomic<bool> flag_{false};
  std::atomic<StopReason> reason_{StopReason::kNone};
};

class JobRunner {
 public:
  using Work = std::function<void(JobControl& control)>;
  // Called instead of the work when a queued job is cancelled or the runner stops before it ran.
  using Dropped = std::function<void(StopReason reason)>;

  explicit JobRunner(size_t max_concurrent);
  ~JobRunner();
  JobRunner(const JobRunner&) = delete;
  JobRunner& operator=(const JobRunner&) = delete;

  // Queues a job; false once Stop() has begun or when max_queued jobs already wait.
  bool Submit(const std::string& job_id, Work work, Dropped dropped, size_t max_queued);

  enum class CancelOutcome { kUnknown, kDequeued, kSignalled };
  // A queued job is removed (its Dropped runs on this thread); a running one is asked to stop.
  CancelOutcome Cancel(const std::string& job_id);

  // Drops every queued job, asks running ones to stop (StopReason::kShutdown), and waits for them.
  void Stop();

  size_t queued() const;
  size_t running() const;

 private:
  struct Entry {
    std::string job_id;
    Work work;
    Dropped dropped;
  };
  void Run();

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Entry> queue_;
  std::map<std::string, std::shared_ptr<JobControl>> running_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace vscan::jobs
