#pragma once
// An exclusive lock on a data directory, so that two servers never share one. The lock is a
// flock on <dir>/vscand.lock, which also holds the owner's pid; the kernel releases it when the
// process ends, however it ends.

#include <filesystem>

#include "vscan/common/status.h"

namespace vscan::guards {

class DataDirLock {
 public:
  // Takes the lock without waiting. FAILED_PRECONDITION naming the holder's pid when another
  // process (or another DataDirLock) holds it; UNAVAILABLE when the lock file cannot be opened.
  static StatusOr<DataDirLock> Acquire(const std::filesystem::path& dir);

  DataDirLock(DataDirLock&& other) noexcept;
  DataDirLock& operator=(DataDirLock&& other) noexcept;
  DataDirLock(const DataDirLock&) = delete;
  DataDirLock& operator=(const DataDirLock&) = delete;
  ~DataDirLock();

 private:
  explicit DataDirLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace vscan::guards
