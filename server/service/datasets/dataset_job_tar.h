#pragma once
// A dataset directory as one uncompressed POSIX tar (ustar): regular files only, sorted by path,
// times and owners zeroed, so the same dataset gives the same bytes.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>

#include "vscan/common/status.h"

namespace vscan::service {

// FailedPrecondition when the files add up to more than max_bytes or a path does not fit ustar's
// 100-byte name field; Internal when a file cannot be read; Cancelled, between files, once *cancel
// is true.
StatusOr<std::string> TarDirectory(const std::filesystem::path& root, uint64_t max_bytes,
                                   const std::atomic<bool>* cancel = nullptr);

}  // namespace vscan::service
