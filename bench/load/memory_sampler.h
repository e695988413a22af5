#pragma once
// Samples a process's resident memory on its own thread while a load runs.

#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace vscan::cli {

struct MemorySummary {
  uint64_t samples = 0;
  uint64_t start_rss_kib = 0;
  uint64_t end_rss_kib = 0;
  // Highest VmRSS sampled, and VmHWM at the end (the peak over the process's whole life).
  uint64_t peak_sampled_rss_kib = 0;
  uint64_t lifetime_peak_rss_kib = 0;
};

class MemorySampler {
 public:
  // Reads pid's memory now and then every period until Stop.
  MemorySampler(pid_t pid, std::chrono::milliseconds period);
  ~MemorySampler();
  MemorySampler(const MemorySampler&) = delete;
  MemorySampler& operator=(const MemorySampler&) = delete;

  // Joins the thread after a last sample; samples is 0 when the process could not be read.
  MemorySummary Stop();

 private:
  void Sample();

  const pid_t pid_;
  const std::chrono::milliseconds period_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  MemorySummary summary_;
  std::thread thread_;
};

}  // namespace vscan::cli
