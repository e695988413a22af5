#pragma once
// Content-addressed files: data/blobs/ab/abcdef... named by the SHA-256 of their bytes.
// Writes go to a temp file, are fsynced, renamed into place, and the directory fsynced.

#include <filesystem>
#include <string>
#include <string_view>

#include "vscan/common/status.h"

namespace vscan::store {

class BlobStore {
 public:
  explicit BlobStore(std::filesystem::path root);

  // Creates the root directory; fails with UNAVAILABLE when it cannot.
  Status Open();
  // Stores bytes durably and returns their lowercase hex SHA-256 (idempotent; a corrupt copy is
  // replaced).
  StatusOr<std::string> Put(std::string_view bytes);
  // Reads a blob back, checking its hash (DATA_LOSS on mismatch, NOT_FOUND when absent).
  // Ids that are not 64 lowercase hex digits are INVALID_ARGUMENT here and in Remove.
  StatusOr<std::string> Get(const std::string& sha256) const;
  bool Contains(const std::string& sha256) const;
  // Deletes a blob; one that is already absent is not an error.
  Status Remove(const std::string& sha256);

 private:
  std::filesystem::path PathOf(const std::string& sha256) const;
  std::filesystem::path root_;
};

// Lowercase hex SHA-256 of bytes.
std::string Sha256Hex(std::string_view bytes);

}  // namespace vscan::store
