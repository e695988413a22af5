#include "store/blob_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

namespace vscan::store {
namespace {

constexpr size_t kHashChunkBytes = 1u << 20;

Status ReadError(const std::filesystem::path& path, int err) {
  return Unavailable("read '" + path.string() + "': " + std::strerror(err));
}

// The lowercase hex SHA-256 of the whole file, read in bounded chunks.
StatusOr<std::string> HashFile(int fd, const std::filesystem::path& path) {
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free);
  if (!ctx || EVP_DigestInit_ex(ctx.get(), EVP_sha256(), nullptr) != 1) return Internal("SHA-256 init failed");
  std::vector<char> buffer(kHashChunkBytes);
  for (off_t offset = 0;;) {
    const ssize_t n = ::pread(fd, buffer.data(), buffer.size(), offset);
    if (n < 0) {
      if (errno == EINTR) continue;
      return ReadError(path, errno);
    }
    if (n == 0) break;
    if (EVP_DigestUpdate(ctx.get(), buffer.data(), static_cast<size_t>(n)) != 1) return Internal("SHA-256 failed");
    offset += n;
  }
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_DigestFinal_ex(ctx.get(), digest.data(), &length) != 1) return Internal("SHA-256 final failed");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 0xf]);
  }
  return hex;
}

}  // namespace

StatusOr<BlobReader> BlobReader::Open(const std::filesystem::path& path, const std::string& sha256) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return NotFound("sha256: no blob '" + sha256 + "'");
    return ReadError(path, errno);
  }
  BlobReader reader(fd, 0, path);
  struct stat st {};
  if (::fstat(fd, &st) != 0) return ReadError(path, errno);
  reader.size_ = static_cast<uint64_t>(st.st_size);
  ASSIGN_OR_RETURN(const std::string actual, HashFile(fd, path));
  if (actual != sha256) return DataLoss("blob '" + sha256 + "' is corrupt: its content hashes to '" + actual + "'");
  return reader;
}

BlobReader::BlobReader(BlobReader&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), size_(other.size_), path_(std::move(other.path_)) {}

BlobReader& BlobReader::operator=(BlobReader&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    size_ = other.size_;
    path_ = std::move(other.path_);
  }
  return *this;
}

BlobReader::~BlobReader() {
  if (fd_ >= 0) ::close(fd_);
}

StatusOr<std::string> BlobReader::Read(uint64_t offset, size_t count) const {
  if (offset >= size_) return std::string();
  std::string bytes(static_cast<size_t>(std::min<uint64_t>(count, size_ - offset)), '\0');
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pread(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
    if (n < 0) {
      if (errno == EINTR) continue;
      return ReadError(path_, errno);
    }
    if (n == 0) return DataLoss("blob '" + path_.filename().string() + "' shrank while it was read");
    done += static_cast<size_t>(n);
  }
  return bytes;
}

}  // namespace vscan::store
