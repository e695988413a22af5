#pragma once
// The bound on the bytes a data directory holds (--max-data-mib): blob files, counted as they are
// written and removed, the directories of dataset jobs, as last measured, plus the catalogue's
// files, read when a write asks for room.

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
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

  // A directory's measured size (a dataset job's), replacing what it was last counted at. Its
  // bytes are on disk already, so this never fails; CheckRoom says whether more may follow.
  void SetDirectoryBytes(const std::string& key, uint64_t bytes);
  void ForgetDirectory(const std::string& key);
  uint64_t DirectoryBytes(const std::string& key) const;
  // RESOURCE_EXHAUSTED naming the limit and what when bytes more would pass max_bytes; reserves
  // nothing. Bytes the directory except_key holds are left out of what is in use (they are part of
  // the bytes asked for, as a resumed dataset's scenes are part of its estimate).
  Status CheckRoom(uint64_t bytes, std::string_view what, const std::string& except_key = "") const;

  uint64_t max_bytes() const { return max_bytes_; }
  // Blob bytes, directories and the counted files.
  uint64_t used_bytes() const;

 private:
  uint64_t CountedFileBytes() const;
  const uint64_t max_bytes_;
  const std::vector<std::filesystem::path> counted_files_;
  mutable std::mutex mutex_;
  uint64_t blob_bytes_ = 0;
  std::map<std::string, uint64_t, std::less<>> directories_;
  uint64_t directory_bytes_ = 0;  // the sum of directories_
};

// The bytes of the regular files under root (symbolic links are not followed); ec says why not.
uint64_t RegularFileBytes(const std::filesystem::path& root, std::error_code& ec);

}  // namespace vscan::store
