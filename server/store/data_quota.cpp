#include "store/data_quota.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <system_error>
#include <utility>

namespace vscan::store {
namespace {

std::string Mib(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

}  // namespace

DataQuota::DataQuota(uint64_t max_bytes, std::vector<std::filesystem::path> counted_files)
    : max_bytes_(max_bytes), counted_files_(std::move(counted_files)) {}

uint64_t RegularFileBytes(const std::filesystem::path& root, std::error_code& ec) {
  ec.clear();
  uint64_t total = 0;
  for (auto it = std::filesystem::recursive_directory_iterator(root, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code size_ec;
    if (it->is_regular_file(size_ec)) {
      const uint64_t size = it->file_size(size_ec);
      if (!size_ec) total += size;
    }
  }
  return total;
}

Status DataQuota::CountExisting(const std::filesystem::path& blob_root) {
  std::error_code ec;
  const uint64_t total = RegularFileBytes(blob_root, ec);
  if (ec) return Unavailable("data directory: cannot count '" + blob_root.string() + "': " + ec.message());
  std::lock_guard lock(mutex_);
  blob_bytes_ += total;
  return Status::Ok();
}

uint64_t DataQuota::CountedFileBytes() const {
  uint64_t total = 0;
  for (const auto& file : counted_files_) {
    std::error_code ec;
    const uint64_t size = std::filesystem::file_size(file, ec);
    if (!ec) total += size;
  }
  return total;
}

Status DataQuota::Reserve(uint64_t bytes) {
  const uint64_t others = CountedFileBytes();
  std::lock_guard lock(mutex_);
  const uint64_t used = blob_bytes_ + directory_bytes_ + others;
  if (bytes > max_bytes_ || used > max_bytes_ - bytes) {
    return ResourceExhausted("data directory: storing " + std::to_string(bytes) + " bytes would pass the limit of " +
                             Mib(max_bytes_) + " (--max-data-mib); " + Mib(used) + " in use");
  }
  blob_bytes_ += bytes;
  return Status::Ok();
}

void DataQuota::Release(uint64_t bytes) {
  std::lock_guard lock(mutex_);
  blob_bytes_ -= std::min(bytes, blob_bytes_);
}

void DataQuota::SetDirectoryBytes(const std::string& key, uint64_t bytes) {
  std::lock_guard lock(mutex_);
  uint64_t& counted = directories_[key];
  directory_bytes_ = directory_bytes_ - counted + bytes;
  counted = bytes;
}

void DataQuota::ForgetDirectory(const std::string& key) {
  std::lock_guard lock(mutex_);
  if (const auto it = directories_.find(key); it != directories_.end()) {
    directory_bytes_ -= it->second;
    directories_.erase(it);
  }
}

uint64_t DataQuota::DirectoryBytes(const std::string& key) const {
  std::lock_guard lock(mutex_);
  const auto it = directories_.find(key);
  return it == directories_.end() ? 0 : it->second;
}

Status DataQuota::CheckRoom(uint64_t bytes, std::string_view what, const std::string& except_key) const {
  const uint64_t others = CountedFileBytes();
  std::lock_guard lock(mutex_);
  uint64_t used = blob_bytes_ + directory_bytes_ + others;
  if (const auto it = directories_.find(except_key); !except_key.empty() && it != directories_.end()) {
    used -= it->second;
  }
  if (bytes > max_bytes_ || used > max_bytes_ - bytes) {
    return ResourceExhausted("data directory: " + std::string(what) + " (about " + Mib(bytes) +
                             ") would pass the limit of " + Mib(max_bytes_) + " (--max-data-mib); " + Mib(used) +
                             " in use");
  }
  return Status::Ok();
}

uint64_t DataQuota::used_bytes() const {
  const uint64_t others = CountedFileBytes();
  std::lock_guard lock(mutex_);
  return blob_bytes_ + directory_bytes_ + others;
}

}  // namespace vscan::store
