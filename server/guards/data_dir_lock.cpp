#include "guards/data_dir_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <string>
#include <system_error>
#include <utility>

namespace vscan::guards {
namespace {

std::string ErrorText(int error) { return std::generic_category().message(error); }

// " (pid N)" from the lock file, or nothing when the holder has not written it yet.
std::string Holder(int fd) {
  char text[32] = {};
  const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
  long pid = 0;
  if (n <= 0 || std::from_chars(text, text + n, pid).ec != std::errc() || pid <= 0) return "";
  return " (pid " + std::to_string(pid) + ")";
}

}  // namespace

StatusOr<DataDirLock> DataDirLock::Acquire(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / "vscand.lock";
  // Close-on-exec: a helper process that inherited it would keep holding the lock.
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return Unavailable("--data-dir: cannot open '" + path.string() + "': " + ErrorText(errno));
  DataDirLock lock(fd);
  while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EINTR) continue;
    if (errno != EWOULDBLOCK) {
      return Unavailable("--data-dir: cannot lock '" + path.string() + "': " + ErrorText(errno));
    }
    return FailedPrecondition("--data-dir: '" + dir.string() + "' is in use by another vscand" + Holder(fd) +
                              "; stop it or choose another data directory");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    return Unavailable("--data-dir: cannot write '" + path.string() + "': " + ErrorText(errno));
  }
  return lock;
}

DataDirLock::DataDirLock(DataDirLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

DataDirLock& DataDirLock::operator=(DataDirLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

DataDirLock::~DataDirLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace vscan::guards
