#include "service/datasets/dataset_directories.h"

#include <spdlog/spdlog.h>

#include <system_error>
#include <utility>

#include "service/datasets/format/durable_file.h"

namespace vscan::service {
namespace {

namespace fs = std::filesystem;

// A directory being removed: "<id>" renamed aside before its files go.
constexpr std::string_view kRemovingPrefix = ".removing-";

Status RemoveTree(const fs::path& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  if (ec) return Unavailable("cannot remove " + path.string() + ": " + ec.message());
  return Status::Ok();
}

}  // namespace

bool IsDatasetDirectoryName(std::string_view name) {
  if (name.size() <= 4 || name.substr(0, 4) != "job_") return false;
  for (const char c : name) {
    const bool word = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    if (!word) return false;
  }
  return true;
}

DatasetDirectories::DatasetDirectories(fs::path data_dir, std::shared_ptr<store::DataQuota> quota)
    : datasets_(std::move(data_dir) / "datasets"), quota_(std::move(quota)) {}

fs::path DatasetDirectories::Root(const std::string& directory_id) const { return datasets_ / directory_id; }

StatusOr<int> DatasetDirectories::Reconcile(const std::set<std::string>& named) {
  std::error_code ec;
  if (!fs::exists(datasets_, ec)) return 0;
  int removed = 0;
  for (auto it = fs::directory_iterator(datasets_, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_ec;
    const bool directory = it->is_directory(type_ec) && !it->is_symlink(type_ec);
    const bool removing = name.rfind(kRemovingPrefix, 0) == 0 &&
                          IsDatasetDirectoryName(std::string_view(name).substr(kRemovingPrefix.size()));
    if (!directory || (!removing && !IsDatasetDirectoryName(name))) {
      spdlog::warn("datasets: '{}' is not a dataset job's directory; left alone", it->path().string());
      continue;
    }
    if (removing || !named.count(name)) {
      // An orphan only costs disk space: one that cannot go now is counted and tried next start.
      const Status gone = RemoveTree(it->path());
      if (gone.ok()) {
        ++removed;
        continue;
      }
      spdlog::warn("datasets: {}", gone.ToString());
    }
    if (quota_) {
      std::error_code size_ec;
      const uint64_t bytes = store::RegularFileBytes(it->path(), size_ec);
      if (size_ec) return Unavailable("cannot measure " + it->path().string() + ": " + size_ec.message());
      quota_->SetDirectoryBytes(name, bytes);
    }
  }
  if (ec) return Unavailable("cannot list " + datasets_.string() + ": " + ec.message());
  if (removed > 0) RETURN_IF_ERROR(dataset::SyncDirectory(datasets_));
  return removed;
}

Status DatasetDirectories::CheckRoom(uint64_t bytes, const std::string& directory_id, std::string_view what) const {
  if (!quota_) return Status::Ok();
  return quota_->CheckRoom(bytes, what, directory_id);
}

Status DatasetDirectories::Charge(const std::string& directory_id, uint64_t bytes, uint64_t next_bytes,
                                  std::string_view what) {
  if (!quota_) return Status::Ok();
  quota_->SetDirectoryBytes(directory_id, bytes);
  return quota_->CheckRoom(next_bytes, what);
}

StatusOr<fs::path> DatasetDirectories::MoveAside(const std::string& directory_id) {
  if (!IsDatasetDirectoryName(directory_id)) {
    return Internal("'" + directory_id + "' does not name a dataset job's directory");
  }
  const fs::path root = Root(directory_id);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(root, ec);
  if (!fs::exists(status)) {
    if (quota_) quota_->ForgetDirectory(directory_id);
    return fs::path();
  }
  if (!fs::is_directory(status)) return Internal(root.string() + " is not a directory; left alone");
  const fs::path aside = datasets_ / (std::string(kRemovingPrefix) + directory_id);
  RETURN_IF_ERROR(RemoveTree(aside));  // left by a removal that failed half-way
  fs::rename(root, aside, ec);
  if (ec) return Unavailable("cannot move " + root.string() + " aside: " + ec.message());
  RETURN_IF_ERROR(dataset::SyncDirectory(datasets_));
  if (quota_) quota_->ForgetDirectory(directory_id);
  return aside;
}

StatusOr<uint64_t> DatasetDirectories::RemoveAside(const fs::path& aside) {
  if (aside.empty()) return uint64_t{0};
  std::error_code size_ec;
  const uint64_t bytes = store::RegularFileBytes(aside, size_ec);
  RETURN_IF_ERROR(RemoveTree(aside));
  return bytes;
}

StatusOr<uint64_t> DatasetDirectories::Remove(const std::string& directory_id) {
  ASSIGN_OR_RETURN(const fs::path aside, MoveAside(directory_id));
  return RemoveAside(aside);
}

}  // namespace vscan::service
