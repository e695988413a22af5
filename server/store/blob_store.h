#pragma once
// Content-addressed files: data/blobs/ab/abcdef... named by the SHA-256 of their bytes.
// Writes go to a temp file, are fsynced, renamed into place, and the directory fsynced.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include <utility>

#include "store/blob_reader.h"
#include "store/data_quota.h"
#include "vscan/common/status.h"

namespace vscan::store {

class BlobStore;

// Keeps a blob from garbage collection while the row that will name it is being written.
class BlobPin {
 public:
  BlobPin(BlobPin&& other) noexcept : store_(std::exchange(other.store_, nullptr)), sha256_(std::move(other.sha256_)) {}
  BlobPin& operator=(BlobPin&&) = delete;
  BlobPin(const BlobPin&) = delete;
  ~BlobPin();
  const std::string& sha256() const { return sha256_; }

 private:
  friend class BlobStore;
  BlobPin(BlobStore* store, std::string sha256) : store_(store), sha256_(std::move(sha256)) {}
  BlobStore* store_;
  std::string sha256_;
};

class BlobStore {
 public:
  explicit BlobStore(std::filesystem::path root);

  // Creates the root directory; fails with UNAVAILABLE when it cannot.
  Status Open();
  // Bounds the bytes new blobs may add (RESOURCE_EXHAUSTED from Put past it); removals give room
  // back. Set before the store is shared.
  void UseQuota(std::shared_ptr<DataQuota> quota) { quota_ = std::move(quota); }
  // Stores bytes durably and returns their lowercase hex SHA-256 (idempotent; a corrupt copy is
  // replaced).
  StatusOr<std::string> Put(std::string_view bytes);
  // Reads a blob back, checking its hash (DATA_LOSS on mismatch, NOT_FOUND when absent).
  // Ids that are not 64 lowercase hex digits are INVALID_ARGUMENT here and in Remove.
  StatusOr<std::string> Get(const std::string& sha256) const;
  // The same checks, the blob left on disk to be read in chunks (bounded memory at any size).
  StatusOr<BlobReader> OpenReader(const std::string& sha256) const;
  bool Contains(const std::string& sha256) const;
  // Put, pinned until the returned pin goes: store the row that names the blob before dropping it.
  StatusOr<BlobPin> PutPinned(std::string_view bytes);
  // Deletes a blob; one that is already absent is not an error.
  Status Remove(const std::string& sha256);
  // Deletes a blob unless it is pinned; returns the bytes freed (0 when pinned or absent). The
  // caller has made sure no row names it.
  StatusOr<uint64_t> RemoveUnpinned(const std::string& sha256);
  bool Pinned(const std::string& sha256) const;
  const std::filesystem::path& root() const { return root_; }

 private:
  friend class BlobPin;
  std::filesystem::path PathOf(const std::string& sha256) const;
  // Writes a new blob's file: a synced temp file renamed into place.
  Status WriteInPlace(const std::filesystem::path& path, const std::string& id, std::string_view bytes);
  void Unpin(const std::string& sha256);
  std::filesystem::path root_;
  std::shared_ptr<DataQuota> quota_;
  mutable std::mutex pins_mutex_;
  // Guards file removal against a concurrent Put of the same content.
  std::map<std::string, int> pins_;
};

// True for names of the form BlobStore gives its files (64 lowercase hex digits).
bool IsBlobName(std::string_view name);

// Lowercase hex SHA-256 of bytes.
std::string Sha256Hex(std::string_view bytes);

}  // namespace vscan::store
