#pragma once
// The cancel flag the reconstruction stages check between (and inside) their loops.

#include <atomic>

namespace vscan::reconstruction {

inline bool Stopped(const std::atomic<bool>* cancel) { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }

}  // namespace vscan::reconstruction
