#pragma once
// Wall time of the stages of a reconstruction, for their stats.

#include <chrono>

namespace vscan::reconstruction {

using StageClock = std::chrono::steady_clock;

inline double MsSince(StageClock::time_point t0) {
  return std::chrono::duration<double, std::milli>(StageClock::now() - t0).count();
}

}  // namespace vscan::reconstruction
