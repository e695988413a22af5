#include "memory_sampler.h"

#include <algorithm>

#include "process_memory.h"

namespace vscan::cli {

MemorySampler::MemorySampler(pid_t pid, std::chrono::milliseconds period) : pid_(pid), period_(period) {
  Sample();
  thread_ = std::thread([this] {
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, period_, [this] { return stopping_; })) {
      lock.unlock();
      Sample();
      lock.lock();
    }
  });
}

MemorySampler::~MemorySampler() {
  if (thread_.joinable()) Stop();
}

MemorySummary MemorySampler::Stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  Sample();
  return summary_;
}

void MemorySampler::Sample() {
  const auto memory = ReadProcessMemory(pid_);
  if (!memory) return;
  std::lock_guard lock(mutex_);
  if (summary_.samples == 0) summary_.start_rss_kib = memory->rss_kib;
  ++summary_.samples;
  summary_.end_rss_kib = memory->rss_kib;
  summary_.peak_sampled_rss_kib = std::max(summary_.peak_sampled_rss_kib, memory->rss_kib);
  summary_.lifetime_peak_rss_kib = std::max(summary_.lifetime_peak_rss_kib, memory->peak_rss_kib);
}

}  // namespace vscan::cli
