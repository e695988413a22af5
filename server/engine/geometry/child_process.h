#pragma once
// Runs a program with bytes on its stdin and collects its stdout, under a wall-clock deadline.
// Safe in a multi-threaded process: fork and exec, close-on-exec pipes, the child always reaped and
// killed by the kernel should the thread that started it die first (PR_SET_PDEATHSIG).

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::geometry {

struct ChildOutcome {
  std::string output;
  bool timed_out = false;        // killed at the deadline
  bool output_too_large = false;  // killed after writing more than max_output bytes
  bool cancelled = false;         // killed because *cancel became true
  int wait_status = 0;           // as waitpid reports it
};

// argv[0] is the program's path (no PATH search). stdin carries input, stdout is collected,
// stderr goes to /dev/null and no other descriptor is inherited. UNAVAILABLE ("cannot start
// '<path>': ...") when the program cannot be started. With cancel, the child is killed within
// about kCancelPollInterval of *cancel becoming true. With max_memory_bytes, the child's data
// (heap and private writable mappings, RLIMIT_DATA) is bounded: its allocations fail past it.
inline constexpr std::chrono::milliseconds kCancelPollInterval{20};
StatusOr<ChildOutcome> RunChild(const std::vector<std::string>& argv, std::string_view input,
                                std::chrono::milliseconds timeout, size_t max_output,
                                const std::atomic<bool>* cancel = nullptr, uint64_t max_memory_bytes = 0);

}  // namespace vscan::geometry
