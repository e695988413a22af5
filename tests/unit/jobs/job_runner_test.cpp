#include "jobs/job_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <vector>

namespace vscan::jobs {
namespace {

using namespace std::chrono_literals;

// Records what the jobs did, in order, and lets a test wait for a condition.
class Journal {
 public:
  void Add(const std::string& entry) {
    {
      std::lock_guard lock(mutex_);
      entries_.push_back(entry);
    }
    changed_.notify_all();
  }
  std::vector<std::string> entries() {
    std::lock_guard lock(mutex_);
    return entries_;
  }
  bool WaitFor(size_t count, std::chrono::milliseconds timeout = 10s) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return entries_.size() >= count; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::string> entries_;
};

// Work that runs until asked to stop, then records why.
JobRunner::Work UntilStopped(Journal& journal, const std::string& name) {
  return [&journal, name](JobControl& control) {
    journal.Add(name + " started");
    while (!control.stop_requested()) std::this_thread::sleep_for(1ms);
    journal.Add(name + (control.reason() == StopReason::kCancelled ? " cancelled" : " shut down"));
  };
}

JobRunner::Dropped Dropped(Journal& journal, const std::string& name) {
  return [&journal, name](StopReason reason) {
    journal.Add(name + (reason == StopReason::kCancelled ? " dropped by cancel" : " dropped by shutdown"));
  };
}

TEST(JobRunnerTest, OneSlotRunsJobsInSubmissionOrderWithoutOverlap) {
  Journal journal;
  std::atomic<int> running{0};
  std::atomic<int> most{0};
  {
    JobRunner runner(1);
    for (int i = 0; i < 5; ++i) {
      const std::string name = "job" + std::to_string(i);
      ASSERT_TRUE(runner.Submit(name, [&, name](JobControl&) {
        most = std::max(most.load(), ++running);
        journal.Add(name);
        std::this_thread::sleep_for(2ms);
        --running;
      }, Dropped(journal, name), 100));
    }
    ASSERT_TRUE(journal.WaitFor(5));
  }
  EXPECT_EQ(journal.entries(), (std::vector<std::string>{"job0", "job1", "job2", "job3", "job4"}));
  EXPECT_EQ(most.load(), 1);
}

TEST(JobRunnerTest, NeverRunsMoreThanItsSlots) {
  Journal journal;
  std::atomic<int> running{0};
  std::atomic<int> most{0};
  JobRunner runner(2);
  for (int i = 0; i < 8; ++i) {
    const std::string name = "job" + std::to_string(i);
    ASSERT_TRUE(runner.Submit(name, [&, name](JobControl&) {
      const int now = ++running;
      int seen = most.load();
      while (now > seen && !most.compare_exchange_weak(seen, now)) {
      }
      std::this_thread::sleep_for(5ms);
      --running;
      journal.Add(name);
    }, Dropped(journal, name), 100));
  }
  ASSERT_TRUE(journal.WaitFor(8));
  EXPECT_EQ(most.load(), 2);
}

TEST(JobRunnerTest, CancelSignalsRunningAndDropsQueued) {
  Journal journal;
  JobRunner runner(1);
  ASSERT_TRUE(runner.Submit("a", UntilStopped(journal, "a"), Dropped(journal, "a"), 100));
  ASSERT_TRUE(runner.Submit("b", UntilStopped(journal, "b"), Dropped(journal, "b"), 100));
  ASSERT_TRUE(journal.WaitFor(1));
  EXPECT_EQ(runner.running(), 1u);
  EXPECT_EQ(runner.queued(), 1u);

  EXPECT_EQ(runner.Cancel("b"), JobRunner::CancelOutcome::kDequeued);
  EXPECT_EQ(runner.Cancel("a"), JobRunner::CancelOutcome::kSignalled);
  EXPECT_EQ(runner.Cancel("nobody"), JobRunner::CancelOutcome::kUnknown);
  ASSERT_TRUE(journal.WaitFor(3));
  EXPECT_EQ(journal.entries(), (std::vector<std::string>{"a started", "b dropped by cancel", "a cancelled"}));
  // A job that has left the runner is unknown to it.
  EXPECT_EQ(runner.Cancel("b"), JobRunner::CancelOutcome::kUnknown);
}

TEST(JobRunnerTest, StopInterruptsRunningDropsQueuedAndRefusesNewWork) {
  Journal journal;
  JobRunner runner(1);
  ASSERT_TRUE(runner.Submit("a", UntilStopped(journal, "a"), Dropped(journal, "a"), 100));
  ASSERT_TRUE(runner.Submit("b", UntilStopped(journal, "b"), Dropped(journal, "b"), 100));
  ASSERT_TRUE(journal.WaitFor(1));
  const auto start = std::chrono::steady_clock::now();
  runner.Stop();
  EXPECT_LT(std::chrono::steady_clock::now() - start, 5s);
  auto entries = journal.entries();
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0], "a started");
  // Both ended by the shutdown, in either order: the running job stops while the queue is dropped.
  std::sort(entries.begin() + 1, entries.end());
  EXPECT_EQ(entries[1], "a shut down");
  EXPECT_EQ(entries[2], "b dropped by shutdown");
  EXPECT_FALSE(runner.Submit("c", UntilStopped(journal, "c"), Dropped(journal, "c"), 100));
  EXPECT_EQ(runner.running(), 0u);
}

TEST(JobRunnerTest, QueueIsBounded) {
  Journal journal;
  JobRunner runner(1);
  ASSERT_TRUE(runner.Submit("a", UntilStopped(journal, "a"), Dropped(journal, "a"), 1));
  ASSERT_TRUE(journal.WaitFor(1));
  ASSERT_TRUE(runner.Submit("b", UntilStopped(journal, "b"), Dropped(journal, "b"), 1));
  EXPECT_FALSE(runner.Submit("c", UntilStopped(journal, "c"), Dropped(journal, "c"), 1));
  EXPECT_EQ(runner.queued(), 1u);
}

}  // namespace
}  // namespace vscan::jobs
