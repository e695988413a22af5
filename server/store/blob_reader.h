#pragma once
// A blob opened for reading in pieces: its hash is checked in one bounded pass when it is opened,
// then it is read a chunk at a time, so that streaming a large blob holds one chunk in memory.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "vscan/common/status.h"

namespace vscan::store {

class BlobReader {
 public:
  // NOT_FOUND when the file is absent, DATA_LOSS when its bytes do not hash to sha256.
  static StatusOr<BlobReader> Open(const std::filesystem::path& path, const std::string& sha256);

  BlobReader(BlobReader&& other) noexcept;
  BlobReader& operator=(BlobReader&& other) noexcept;
  BlobReader(const BlobReader&) = delete;
  BlobReader& operator=(const BlobReader&) = delete;
  ~BlobReader();

  uint64_t size() const { return size_; }
  // Up to count bytes from offset (fewer at the end). The file stays open, so a blob collected
  // meanwhile still reads as it was verified.
  StatusOr<std::string> Read(uint64_t offset, size_t count) const;

 private:
  BlobReader(int fd, uint64_t size, std::filesystem::path path) : fd_(fd), size_(size), path_(std::move(path)) {}

  int fd_ = -1;
  uint64_t size_ = 0;
  std::filesystem::path path_;
};

}  // namespace vscan::store
