#pragma once
// A long loop's cancel flag, which callers may leave null.

#include <atomic>

namespace vscan {

inline bool IsCancelled(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

}  // namespace vscan
