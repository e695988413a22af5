#pragma once
// The directories dataset jobs write, <data dir>/datasets/<id of the job that started it>: counted
// against --max-data-mib as they grow, removed with the last job that names them, and swept of
// directories no job names when the server starts.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>

#include "store/data_quota.h"
#include "vscan/common/status.h"

namespace vscan::service {

// "job_" and letters, digits or '_': the only names removed or swept (never ".", ".." or a path).
bool IsDatasetDirectoryName(std::string_view name);

class DatasetDirectories {
 public:
  // quota may be null (no --max-data-mib): sizes are then not tracked.
  DatasetDirectories(std::filesystem::path data_dir, std::shared_ptr<store::DataQuota> quota);

  std::filesystem::path Root(const std::string& directory_id) const;

  // Held while the jobs naming a directory are read and it is moved aside, and while a job that
  // resumes a directory is recorded: a directory is never removed under a job just admitted to it.
  std::unique_lock<std::mutex> HoldNames() { return std::unique_lock(names_mutex_); }

  // At start, before any job runs: removes the directories no job names (named: the ids of the
  // jobs that started them) and those a removal left, and counts the others into the quota (and
  // any it could not remove, tried again next start). Returns how many it removed; an error only
  // when the directory cannot be listed or measured.
  StatusOr<int> Reconcile(const std::set<std::string>& named);

  // Whether bytes more fit the quota, leaving out what directory_id holds already (a resumed
  // dataset's scenes are part of its estimate). RESOURCE_EXHAUSTED names what and the flag.
  Status CheckRoom(uint64_t bytes, const std::string& directory_id, std::string_view what) const;
  // The directory holds bytes now; RESOURCE_EXHAUSTED naming what when next_bytes more would pass
  // the quota. The bytes are counted either way: they are on disk.
  Status Charge(const std::string& directory_id, uint64_t bytes, uint64_t next_bytes, std::string_view what);

  // Renames the directory aside (flushed, so that a crash cannot bring it back) and gives its bytes
  // back to the quota; returns where it now is, empty when there was none.
  StatusOr<std::filesystem::path> MoveAside(const std::string& directory_id);
  // Removes what MoveAside returned; returns the bytes removed.
  StatusOr<uint64_t> RemoveAside(const std::filesystem::path& aside);
  // Both in turn.
  StatusOr<uint64_t> Remove(const std::string& directory_id);

 private:
  const std::filesystem::path datasets_;
  const std::shared_ptr<store::DataQuota> quota_;
  std::mutex names_mutex_;
};

}  // namespace vscan::service
