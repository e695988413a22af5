#include "reconstruction/poisson_process.h"

#include <sys/wait.h>

#include <chrono>
#include <cstring>
#include <limits>

#include "geometry/child_process.h"

namespace vscan::reconstruction {
namespace {

constexpr char kInputMagic[4] = {'V', 'P', 'I', '1'};
constexpr char kResultMagic[4] = {'V', 'P', 'R', '1'};
// Far past any depth-10 mesh; only a broken helper reaches it.
constexpr size_t kMaxResultBytes = size_t{8} << 30;
// The job's cancel, not a clock, ends a slow solve.
constexpr std::chrono::hours kNoDeadline{24 * 365};

template <typename T>
void Put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

template <typename T>
void PutArray(std::string& out, const T* data, size_t count) {
  out.append(reinterpret_cast<const char*>(data), count * sizeof(T));
}

class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  template <typename T>
  bool Get(T& value) {
    return GetArray(&value, 1);
  }
  template <typename T>
  bool GetArray(T* data, size_t count) {
    if (count > (bytes_.size() - offset_) / sizeof(T)) return false;
    std::memcpy(static_cast<void*>(data), bytes_.data() + offset_, count * sizeof(T));
    offset_ += count * sizeof(T);
    return true;
  }
  bool Magic(const char (&magic)[4]) {
    if (bytes_.size() - offset_ < 4 || std::memcmp(bytes_.data() + offset_, magic, 4) != 0) return false;
    offset_ += 4;
    return true;
  }
  bool AtEnd() const { return offset_ == bytes_.size(); }
  size_t Left() const { return bytes_.size() - offset_; }

 private:
  std::string_view bytes_;
  size_t offset_ = 0;
};

}  // namespace

uint64_t EstimatePoissonBytes(size_t points, int depth) {
  constexpr uint64_t kBytesPerPoint = 150;  // the frame, the PCL cloud and the solver's samples
  constexpr uint64_t kBytesPerSurfaceCell = 48;
  constexpr uint64_t kFixedBytes = uint64_t{32} << 20;
  const int d = std::max(depth, 1);
  return kFixedBytes + kBytesPerPoint * points + kBytesPerSurfaceCell * (uint64_t{1} << (2 * d));
}

std::string EncodePoissonInput(std::span<const Eigen::Vector3f> points, std::span<const Eigen::Vector3f> normals,
                               const PoissonOptions& options) {
  std::string out;
  out.reserve(24 + points.size() * 24);
  out.append(kInputMagic, 4);
  Put(out, static_cast<int32_t>(options.depth));
  Put(out, static_cast<int32_t>(options.threads));
  Put(out, static_cast<uint64_t>(points.size()));
  for (const Eigen::Vector3f& p : points) PutArray(out, p.data(), 3);
  for (const Eigen::Vector3f& n : normals) PutArray(out, n.data(), 3);
  return out;
}

StatusOr<PoissonInput> DecodePoissonInput(std::string_view bytes) {
  Reader in(bytes);
  PoissonInput input;
  int32_t depth = 0, threads = 0;
  uint64_t count = 0;
  if (!in.Magic(kInputMagic) || !in.Get(depth) || !in.Get(threads) || !in.Get(count) ||
      count > in.Left() / 24) {
    return InvalidArgument("poisson input: bad header");
  }
  input.options.depth = depth;
  input.options.threads = threads;
  input.points.resize(count);
  input.normals.resize(count);
  for (auto& p : input.points) in.GetArray(p.data(), 3);
  for (auto& n : input.normals) in.GetArray(n.data(), 3);
  if (!in.AtEnd()) return InvalidArgument("poisson input: trailing bytes");
  return input;
}

std::string EncodePoissonResult(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(20 + mesh.vertices.size() * 12 + mesh.triangles.size() * 12);
  out.append(kResultMagic, 4);
  Put(out, static_cast<uint64_t>(mesh.vertices.size()));
  Put(out, static_cast<uint64_t>(mesh.triangles.size()));
  for (const Eigen::Vector3f& v : mesh.vertices) PutArray(out, v.data(), 3);
  for (const auto& t : mesh.triangles) PutArray(out, t.data(), 3);
  return out;
}

StatusOr<TriangleMesh> DecodePoissonResult(std::string_view bytes) {
  Reader in(bytes);
  uint64_t vertices = 0, triangles = 0;
  if (!in.Magic(kResultMagic) || !in.Get(vertices) || !in.Get(triangles) || vertices > in.Left() / 12 ||
      triangles > in.Left() / 12 || (vertices + triangles) * 12 != in.Left()) {
    return Internal("poisson helper: malformed result");
  }
  TriangleMesh mesh;
  mesh.vertices.resize(vertices);
  mesh.triangles.resize(triangles);
  for (auto& v : mesh.vertices) in.GetArray(v.data(), 3);
  for (auto& t : mesh.triangles) in.GetArray(t.data(), 3);
  for (const auto& t : mesh.triangles) {
    for (uint32_t index : t) {
      if (index >= vertices) return Internal("poisson helper: triangle index out of range");
    }
  }
  return mesh;
}

StatusOr<TriangleMesh> PoissonInChild(const std::string& helper_path, std::span<const Eigen::Vector3f> points,
                                      std::span<const Eigen::Vector3f> normals, const PoissonOptions& options,
                                      const std::atomic<bool>* cancel, uint64_t max_memory_bytes) {
  if (points.size() != normals.size()) return InvalidArgument("normals: one per point is needed");
  if (options.depth < 1 || options.depth > 14) return InvalidArgument("poisson.depth: must lie in [1, 14]");
  if (points.empty()) return TriangleMesh{};
  const std::string input = EncodePoissonInput(points, normals, options);
  auto run = geometry::RunChild({helper_path}, input, kNoDeadline, kMaxResultBytes, cancel, max_memory_bytes);
  if (!run.ok()) return Status(run.status().code(), "poisson helper: " + run.status().message());
  if (run->cancelled) return Cancelled("reconstruction stopped");
  if (run->output_too_large) return Internal("poisson helper: result exceeds its bound");
  const int status = run->wait_status;
  if (WIFSIGNALED(status)) {
    return Internal("poisson helper: stopped by signal " + std::to_string(WTERMSIG(status)) +
                    " (out of memory?)");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kPoissonOutOfMemoryExit) {
    return ResourceExhausted("poisson.depth", "depth " + std::to_string(options.depth) + " over " +
                                                  std::to_string(points.size()) + " points passed the bound of " +
                                                  std::to_string(max_memory_bytes >> 20) + " MiB while solving");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return Internal("poisson helper: exited with status " + std::to_string(WEXITSTATUS(status)));
  }
  return DecodePoissonResult(run->output);
}

}  // namespace vscan::reconstruction
