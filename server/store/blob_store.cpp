#include "store/blob_store.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <openssl/evp.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <system_error>
#include <utility>

namespace vscan::store {
namespace {

// A full disk or quota is RESOURCE_EXHAUSTED (free space, then retry); other storage trouble
// the caller may retry after (I/O, permissions) is UNAVAILABLE; anything else from the OS points
// at a bug or a broken setup.
Status OsError(const std::string& what, const std::filesystem::path& path, int err) {
  std::string message = what + " '" + path.string() + "': " + std::strerror(err);
  switch (err) {
    case ENOSPC:
    case EDQUOT:
      return ResourceExhausted(what + " '" + path.string() + "': no space left (" + std::strerror(err) + ")");
    case EIO:
    case EROFS:
    case EACCES:
    case EPERM:
    case EMFILE:
    case ENFILE:
    case ENOMEM:
    case EBUSY:
    case EAGAIN:
      return Unavailable(std::move(message));
    default:
      return Internal(std::move(message));
  }
}

bool IsValidId(std::string_view id) { return IsBlobName(id); }

Status CheckId(const std::string& id) {
  if (IsValidId(id)) return Status::Ok();
  return InvalidArgument("sha256: '" + id.substr(0, 80) + "' is not 64 lowercase hex digits");
}

// Closes a descriptor on scope exit unless released.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_;
};

Status SyncDirectory(const std::filesystem::path& dir) {
  Fd fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) return OsError("open directory", dir, errno);
  if (::fsync(fd.get()) != 0) return OsError("fsync directory", dir, errno);
  return Status::Ok();
}

// Creates dir if missing; when this call made it, the parent's entry is synced too.
Status EnsureDirectory(const std::filesystem::path& dir) {
  if (::mkdir(dir.c_str(), 0755) == 0) return SyncDirectory(dir.parent_path());
  if (errno != EEXIST) return OsError("create directory", dir, errno);
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) return OsError("stat", dir, errno);
  if (!S_ISDIR(st.st_mode)) return OsError("create directory", dir, ENOTDIR);
  return Status::Ok();
}

Status WriteAll(int fd, std::string_view bytes, const std::filesystem::path& path) {
  while (!bytes.empty()) {
    ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return OsError("write", path, errno);
    }
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return Status::Ok();
}

// Space a blob leaves free on its filesystem, so that the catalogue can still record deletes and
// the ends of jobs (and open at all) once blobs have filled the disk.
constexpr uint64_t kCatalogueReserveBytes = 1u << 20;

// Writes bytes to a fresh temp file in dir and syncs it; returns the temp file's path.
StatusOr<std::filesystem::path> WriteTempFile(const std::filesystem::path& dir, const std::string& id,
                                              std::string_view bytes) {
  std::string name = (dir / ("." + id + ".tmp.XXXXXX")).string();
  Fd fd(::mkostemp(name.data(), O_CLOEXEC));
  if (fd.get() < 0) return OsError("create temp file in", dir, errno);
  std::filesystem::path tmp(name);
  struct statvfs fs {};
  if (::fstatvfs(fd.get(), &fs) == 0 &&
      uint64_t{fs.f_bavail} * fs.f_frsize < bytes.size() + kCatalogueReserveBytes) {
    ::unlink(tmp.c_str());
    return ResourceExhausted("write '" + tmp.string() + "': no space left (" + std::to_string(bytes.size()) +
                             " bytes to write, " + std::to_string(uint64_t{fs.f_bavail} * fs.f_frsize) +
                             " free, 1 MiB of which stays for the catalogue)");
  }
  Status status = WriteAll(fd.get(), bytes, tmp);
  if (status.ok() && ::fsync(fd.get()) != 0) status = OsError("fsync", tmp, errno);
  if (status.ok() && ::close(fd.release()) != 0) status = OsError("close", tmp, errno);
  if (!status.ok()) {
    ::unlink(tmp.c_str());
    return status;
  }
  return tmp;
}

StatusOr<std::string> ReadAll(const std::filesystem::path& path) {
  Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) return OsError("open", path, errno);
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) return OsError("stat", path, errno);
  std::string bytes;
  bytes.reserve(static_cast<size_t>(st.st_size));
  std::array<char, 1 << 16> buffer;
  for (;;) {
    ssize_t n = ::read(fd.get(), buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return OsError("read", path, errno);
    }
    if (n == 0) break;
    bytes.append(buffer.data(), static_cast<size_t>(n));
  }
  return bytes;
}

}  // namespace

BlobStore::BlobStore(std::filesystem::path root) : root_(std::move(root)) {}

Status BlobStore::Open() {
  std::error_code ec;
  std::filesystem::create_directories(root_, ec);
  if (ec) return Unavailable("blob store: cannot create '" + root_.string() + "': " + ec.message());
  if (!std::filesystem::is_directory(root_, ec)) {
    return Unavailable("blob store: '" + root_.string() + "' is not a directory");
  }
  return Status::Ok();
}

BlobPin::~BlobPin() {
  if (store_ != nullptr) store_->Unpin(sha256_);
}

StatusOr<std::string> BlobStore::Put(std::string_view bytes) {
  ASSIGN_OR_RETURN(BlobPin pin, PutPinned(bytes));
  return pin.sha256();
}

StatusOr<BlobPin> BlobStore::PutPinned(std::string_view bytes) {
  std::string id = Sha256Hex(bytes);
  if (id.empty()) return Internal("blob store: SHA-256 computation failed");
  {
    // Pinned before the existence check below, so a collection cannot unlink the file after it.
    std::lock_guard lock(pins_mutex_);
    ++pins_[id];
  }
  BlobPin pin(this, id);
  std::filesystem::path path = PathOf(id);

  // Content addressing makes a second Put a no-op, unless the stored copy went bad.
  if (auto existing = ReadAll(path); existing.ok() && Sha256Hex(*existing) == id) return pin;

  if (quota_) RETURN_IF_ERROR(quota_->Reserve(bytes.size()));
  Status written = WriteInPlace(path, id, bytes);
  if (!written.ok()) {
    if (quota_) quota_->Release(bytes.size());
    return written;
  }
  return pin;
}

Status BlobStore::WriteInPlace(const std::filesystem::path& path, const std::string& id, std::string_view bytes) {
  RETURN_IF_ERROR(EnsureDirectory(path.parent_path()));
  ASSIGN_OR_RETURN(std::filesystem::path tmp, WriteTempFile(path.parent_path(), id, bytes));
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    int err = errno;
    ::unlink(tmp.c_str());
    return OsError("rename into", path, err);
  }
  return SyncDirectory(path.parent_path());
}

void BlobStore::Unpin(const std::string& sha256) {
  std::lock_guard lock(pins_mutex_);
  if (auto it = pins_.find(sha256); it != pins_.end() && --it->second == 0) pins_.erase(it);
}

bool BlobStore::Pinned(const std::string& sha256) const {
  std::lock_guard lock(pins_mutex_);
  return pins_.contains(sha256);
}

StatusOr<uint64_t> BlobStore::RemoveUnpinned(const std::string& sha256) {
  RETURN_IF_ERROR(CheckId(sha256));
  std::lock_guard lock(pins_mutex_);
  if (pins_.contains(sha256)) return 0;
  std::filesystem::path path = PathOf(sha256);
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return 0;
    return OsError("stat", path, errno);
  }
  RETURN_IF_ERROR(Remove(sha256));
  return static_cast<uint64_t>(st.st_size);
}

StatusOr<std::string> BlobStore::Get(const std::string& sha256) const {
  RETURN_IF_ERROR(CheckId(sha256));
  std::filesystem::path path = PathOf(sha256);
  auto bytes = ReadAll(path);
  if (!bytes.ok()) {
    if (::access(path.c_str(), F_OK) != 0 && errno == ENOENT) {
      return NotFound("sha256: no blob '" + sha256 + "'");
    }
    return bytes.status();
  }
  std::string actual = Sha256Hex(*bytes);
  if (actual.empty()) return Internal("blob store: SHA-256 computation failed");
  if (actual != sha256) {
    return DataLoss("blob '" + sha256 + "' is corrupt: its content hashes to '" + actual + "'");
  }
  return std::move(bytes).value();
}

StatusOr<BlobReader> BlobStore::OpenReader(const std::string& sha256) const {
  RETURN_IF_ERROR(CheckId(sha256));
  return BlobReader::Open(PathOf(sha256), sha256);
}

bool BlobStore::Contains(const std::string& sha256) const {
  if (!IsValidId(sha256)) return false;
  struct stat st {};
  return ::stat(PathOf(sha256).c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

Status BlobStore::Remove(const std::string& sha256) {
  RETURN_IF_ERROR(CheckId(sha256));
  std::filesystem::path path = PathOf(sha256);
  struct stat st {};
  const bool sized = quota_ && ::stat(path.c_str(), &st) == 0;
  if (::unlink(path.c_str()) != 0) {
    if (errno == ENOENT) return Status::Ok();
    return OsError("remove", path, errno);
  }
  if (sized) quota_->Release(static_cast<uint64_t>(st.st_size));
  return SyncDirectory(path.parent_path());
}

std::filesystem::path BlobStore::PathOf(const std::string& sha256) const {
  return root_ / sha256.substr(0, 2) / sha256;
}

bool IsBlobName(std::string_view name) {
  if (name.size() != 64) return false;
  for (char c : name) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

std::string Sha256Hex(std::string_view bytes) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1) {
    return {};
  }
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 0xf]);
  }
  return hex;
}

}  // namespace vscan::store
