#pragma once
// Bulk copies into memory that is written once and not read again soon (the output cloud).

#include <cstddef>

namespace vscan::raycast {

// Copies with full-line non-temporal stores where the CPU has them: the destination lines are
// neither read first nor left in the cache, which would evict the acceleration structure.
// Falls back to memcpy. Call StreamFence() before another thread reads the destination.
void StreamCopy(void* dst, const void* src, size_t bytes);
void StreamFence();

}  // namespace vscan::raycast
