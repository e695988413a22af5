#include "vscan/common/cloud_file_writer.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "cloud_columns.h"

namespace vscan {
namespace {

static_assert(std::endian::native == std::endian::little, "binary files are written in native little-endian");

using cloud_file::Column;

std::string ErrnoText() { return std::strerror(errno); }

using Format = CloudFileFormat;

std::string Header(Format format, const std::vector<Column>& cols, uint64_t points, std::optional<size_t> pad) {
  return format == Format::kPly ? cloud_file::PlyHeader(cols, points, pad) : cloud_file::PcdHeader(cols, points, pad);
}

// Points interleaved into one write at a time.
constexpr size_t kBlockPoints = 16384;

}  // namespace

std::optional<CloudFileFormat> CloudFileFormatOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".ply") return Format::kPly;
  if (ext == ".pcd") return Format::kPcd;
  return std::nullopt;
}

struct CloudFileWriter::State {
  std::string path, tmp;
  std::FILE* file = nullptr;
  Format format = Format::kPly;
  uint32_t fields = kFieldPosition;
  std::optional<uint64_t> announced;
  size_t header_bytes = 0;
  uint64_t points = 0;
  std::vector<char> block;
  bool finished = false;

  ~State() { Abandon(); }

  // Closes and removes the temporary file unless it was renamed into place.
  void Abandon() {
    if (file) std::fclose(file);
    file = nullptr;
    if (!finished && !tmp.empty()) std::remove(tmp.c_str());
    finished = true;
  }

  // After a failed write: the temporary file goes, the error stays.
  Status Fail(const std::string& what) {
    const std::string msg = path + ": " + what + ": " + ErrnoText();
    Abandon();
    return DataLoss(msg);
  }

  std::vector<Column> HeaderColumns() const {
    PointCloud probe;
    probe.fields = fields;
    return cloud_file::Columns(probe);
  }
};

CloudFileWriter::CloudFileWriter(std::unique_ptr<State> state) : state_(std::move(state)) {}
CloudFileWriter::CloudFileWriter(CloudFileWriter&&) noexcept = default;
CloudFileWriter& CloudFileWriter::operator=(CloudFileWriter&&) noexcept = default;
CloudFileWriter::~CloudFileWriter() = default;

StatusOr<CloudFileWriter> CloudFileWriter::Open(const std::string& path, CloudFileFormat format, uint32_t fields,
                                                std::optional<uint64_t> points) {
  static std::atomic<unsigned> counter{0};
  auto s = std::make_unique<State>();
  s->path = path;
  s->format = format;
  s->fields = fields | kFieldPosition;
  s->announced = points;
  const std::string tmp = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  s->file = std::fopen(tmp.c_str(), "wb");
  if (!s->file) {
    const int err = errno;
    const std::string msg = path + ": cannot create: " + std::strerror(err);
    return err == ENOENT ? NotFound(msg) : FailedPrecondition(msg);
  }
  s->tmp = tmp;
  // An unknown count is written later over a header sized for the longest count.
  const auto cols = s->HeaderColumns();
  const std::string header = points ? Header(s->format, cols, *points, std::nullopt)
                                    : Header(s->format, cols, std::numeric_limits<uint64_t>::max(), 0);
  s->header_bytes = header.size();
  if (std::fwrite(header.data(), 1, header.size(), s->file) != header.size()) return s->Fail("short write");
  return CloudFileWriter(std::move(s));
}

Status CloudFileWriter::Append(const PointCloud& block) {
  State& s = *state_;
  if (s.finished || !s.file) return FailedPrecondition(s.path + ": append after the file was finished");
  if ((block.fields | kFieldPosition) != s.fields) {
    return InvalidArgument(s.path + ": block fields differ from the file's");
  }
  RETURN_IF_ERROR(cloud_file::CheckConsistent(block));
  const auto cols = cloud_file::Columns(block);
  const size_t record = cloud_file::RecordBytes(cols);
  const size_t n = block.size();
  s.block.resize(std::min(n, kBlockPoints) * record);
  for (size_t begin = 0; begin < n; begin += kBlockPoints) {
    const size_t count = std::min(kBlockPoints, n - begin);
    char* out = s.block.data();
    for (size_t i = begin; i < begin + count; ++i) {
      for (const Column& c : cols) {
        std::memcpy(out, c.base + i * c.step, c.size);
        out += c.size;
      }
    }
    if (std::fwrite(s.block.data(), 1, count * record, s.file) != count * record) return s.Fail("short write");
  }
  s.points += n;
  return Status::Ok();
}

Status CloudFileWriter::Finish() {
  State& s = *state_;
  if (s.finished || !s.file) return FailedPrecondition(s.path + ": finished twice");
  if (s.announced && *s.announced != s.points) {
    s.Abandon();
    return DataLoss(s.path + ": " + std::to_string(s.points) + " points written, " + std::to_string(*s.announced) +
                    " announced");
  }
  if (!s.announced) {
    const auto cols = s.HeaderColumns();
    const size_t unpadded = Header(s.format, cols, s.points, 0).size();
    const std::string header = Header(s.format, cols, s.points, s.header_bytes - unpadded);
    if (std::fflush(s.file) != 0) return s.Fail("short write");
    if (std::fseek(s.file, 0, SEEK_SET) != 0) return s.Fail("seek");
    if (std::fwrite(header.data(), 1, header.size(), s.file) != header.size()) return s.Fail("short write");
  }
  if (std::fflush(s.file) != 0) return s.Fail("short write");
  if (::fsync(::fileno(s.file)) != 0) return s.Fail("fsync");
  const int closed = std::fclose(s.file);
  s.file = nullptr;
  if (closed != 0) return s.Fail("close");
  if (std::rename(s.tmp.c_str(), s.path.c_str()) != 0) return s.Fail("rename");
  s.finished = true;
  return Status::Ok();
}

uint64_t CloudFileWriter::points() const { return state_->points; }

}  // namespace vscan
