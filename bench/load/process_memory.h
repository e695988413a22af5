#pragma once
// The resident memory of a local process from /proc, and which process listens on a TCP port.

#include <sys/types.h>

#include <cstdint>
#include <optional>

namespace vscan::cli {

struct ProcessMemory {
  // VmRSS and VmHWM (the peak of VmRSS over the process's life), KiB.
  uint64_t rss_kib = 0;
  uint64_t peak_rss_kib = 0;
};

// nullopt when the process is gone or its status cannot be read.
std::optional<ProcessMemory> ReadProcessMemory(pid_t pid);

// The process holding a listening TCP socket (IPv4 or IPv6) on port, found through
// /proc/net/tcp{,6} and the socket links in /proc/*/fd; only this user's processes are visible.
std::optional<pid_t> FindListeningProcess(uint16_t port);

}  // namespace vscan::cli
