#include "service/datasets/format/durable_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace vscan::service::dataset {
namespace {

Status Failure(const std::string& what, const std::filesystem::path& path) {
  return Internal(what + " " + path.string() + ": " + std::strerror(errno));
}

}  // namespace

Status WriteFileDurably(const std::filesystem::path& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Failure("cannot create", path);
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const Status failed = Failure("cannot write", path);
      ::close(fd);
      return failed;
    }
    written += size_t(n);
  }
  if (::fsync(fd) != 0) {
    const Status failed = Failure("cannot flush", path);
    ::close(fd);
    return failed;
  }
  if (::close(fd) != 0) return Failure("cannot close", path);
  return Status::Ok();
}

Status SyncDirectory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Failure("cannot open directory", dir);
  const bool synced = ::fsync(fd) == 0;
  const Status failed = synced ? Status::Ok() : Failure("cannot flush directory", dir);
  ::close(fd);
  return failed;
}

Status RenameDurably(const std::filesystem::path& from, const std::filesystem::path& to) {
  if (::rename(from.c_str(), to.c_str()) != 0) return Failure("cannot rename " + from.string() + " to", to);
  return SyncDirectory(to.parent_path());
}

Status ReplaceFileDurably(const std::filesystem::path& path, std::string_view bytes, std::string_view temp_suffix) {
  const std::filesystem::path temporary = path.string() + std::string(temp_suffix);
  RETURN_IF_ERROR(WriteFileDurably(temporary, bytes));
  return RenameDurably(temporary, path);
}

StatusOr<std::string> ReadWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return NotFound("cannot open " + path.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) return DataLoss("cannot read " + path.string());
  return std::move(bytes).str();
}

}  // namespace vscan::service::dataset
