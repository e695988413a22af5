#pragma once
// The bound on the bytes a data directory holds (--max-data-mib): blob files, counted as they are
// written and removed, plus the catalogue's files, read when a write asks for room.

#include <cstdint>
#include <filesystem>
#include <mutex>
#include <vector>

#include "vscan/common/status.h"

namespace vscan::store {

class DataQuota {
 public:
  // counted_files: files outside the blob store that count too (the catalogue and its journal);
  // their current size is read at each Reserve.
  DataQuota(uint64_t max_bytes, std::vector<std::filesystem::path> counted_files);

  // Adds the sizes of the regular files already under blob_root.
  Status CountExisting(const std::filesystem::path& blob_root);
  // Takes room for bytes more; RESOURCE_EXHAUSTED naming the limit when it would pass max_bytes.
  Status Reserve(uint64_t bytes);
  // Gives back room from a failed write or a removed blob.
  void Release(uint64_t bytes);
  uint64_t max_bytes() const { return max_bytes_; }
  // Blob bytes plus the counted files.
  uint64_t used_bytes() const;

 private:
  uint64_t CountedFileBytes() const;
  const uint64_t max_bytes_;
  const std::vector<std::filesystem::path> counted_files_;
  mutable std::mutex mutex_;
  uint64_t blob_bytes_ = 0;
};

}  // namespace vscan::store
