// vscan-mesh-import: parses one mesh file from stdin under resource limits and writes the framed
// result (geometry/import_protocol.h) to stdout. vscand runs it for every upload, so that an
// importer that aborts, hangs or exhausts memory takes down only this process.

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

#include "geometry/import_protocol.h"
#include "geometry/mesh_import.h"

#if defined(__SANITIZE_ADDRESS__)
#define VSCAN_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VSCAN_ADDRESS_SANITIZER 1
#endif
#endif

namespace {

using vscan::Status;
using vscan::StatusOr;
using vscan::TriangleMesh;
namespace geometry = vscan::geometry;

constexpr int kUsageError = 2;
constexpr uint64_t kDefaultMemoryBytes = uint64_t{8} << 30;
constexpr uint64_t kDefaultCpuSeconds = 60;
constexpr rlim_t kMaxOpenFiles = 16;
constexpr size_t kReadChunk = size_t{1} << 20;

struct Arguments {
  geometry::MeshFileFormat format;
  double metres_per_unit;
  uint64_t memory_bytes = kDefaultMemoryBytes;
  uint64_t cpu_seconds = kDefaultCpuSeconds;
};

std::optional<uint64_t> ParseCount(std::string_view text) {
  uint64_t value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value == 0) return std::nullopt;
  return value;
}

// strtod, unlike from_chars, reads the "%a" form with its 0x prefix.
std::optional<double> ParseDouble(const char* text) {
  char* end = nullptr;
  errno = 0;
  double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE) return std::nullopt;
  return value;
}

std::optional<Arguments> Parse(int argc, char** argv) {
  if (argc < 3 || argc > 5) return std::nullopt;
  auto format = geometry::ParseMeshFileFormat(argv[1]);
  auto metres_per_unit = ParseDouble(argv[2]);
  if (!format || !metres_per_unit) return std::nullopt;
  Arguments args{*format, *metres_per_unit};
  if (argc > 3) {
    auto memory = ParseCount(argv[3]);
    if (!memory) return std::nullopt;
    args.memory_bytes = *memory;
  }
  if (argc > 4) {
    auto cpu = ParseCount(argv[4]);
    if (!cpu) return std::nullopt;
    args.cpu_seconds = *cpu;
  }
  return args;
}

// Lowers a limit; never asks for more than the current hard limit, which would fail.
Status Limit(int resource, const char* name, rlim_t soft, rlim_t hard) {
  rlimit current{};
  if (getrlimit(resource, &current) != 0) {
    return vscan::Internal(std::string("mesh importer: cannot read ") + name + ": " + std::strerror(errno));
  }
  rlimit wanted{std::min(soft, current.rlim_max), std::min(hard, current.rlim_max)};
  if (setrlimit(resource, &wanted) != 0) {
    return vscan::Internal(std::string("mesh importer: cannot limit ") + name + ": " + std::strerror(errno));
  }
  return Status::Ok();
}

Status ApplyLimits(const Arguments& args) {
  Status status = Limit(RLIMIT_CORE, "RLIMIT_CORE", 0, 0);
  if (status.ok()) status = Limit(RLIMIT_FSIZE, "RLIMIT_FSIZE", 0, 0);
  if (status.ok()) status = Limit(RLIMIT_NOFILE, "RLIMIT_NOFILE", kMaxOpenFiles, kMaxOpenFiles);
  // SIGXCPU at the soft limit, SIGKILL a second later should that be handled.
  if (status.ok()) status = Limit(RLIMIT_CPU, "RLIMIT_CPU", args.cpu_seconds, args.cpu_seconds + 1);
#ifndef VSCAN_ADDRESS_SANITIZER  // the sanitizer reserves terabytes of address space up front
  if (status.ok()) status = Limit(RLIMIT_AS, "RLIMIT_AS", args.memory_bytes, args.memory_bytes);
#endif
  return status;
}

bool ReadAll(int fd, std::string& out) {
  for (;;) {
    const size_t before = out.size();
    out.resize(before + kReadChunk);
    ssize_t n = read(fd, out.data() + before, kReadChunk);
    out.resize(before + static_cast<size_t>(n > 0 ? n : 0));
    if (n == 0) return true;
    if (n < 0 && errno != EINTR) return false;
  }
}

bool WriteAll(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    ssize_t n = write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<size_t>(n));
  }
  return true;
}

bool WriteResult(const StatusOr<TriangleMesh>& result) {
  const geometry::EncodedImportResult encoded = geometry::EncodeImportResult(result);
  return WriteAll(STDOUT_FILENO, encoded.header) && WriteAll(STDOUT_FILENO, encoded.payload);
}

// Lets tests stand in for an importer that aborts or never finishes.
void MaybeMisbehaveForTest() {
  const char* mode = std::getenv("VSCAN_MESH_IMPORT_TEST_CRASH");
  if (mode == nullptr) return;
  if (std::string_view(mode) == "abort") std::abort();
  if (std::string_view(mode) == "hang") {
    for (;;) pause();
  }
}

bool allocation_failed = false;

// assimp turns a std::bad_alloc into an ordinary parse error; this notices it all the same.
void OnAllocationFailure() {
  allocation_failed = true;
  throw std::bad_alloc();
}

Status OutOfMemory(const Arguments& args) {
  return vscan::ResourceExhausted("mesh data: importing the file needs more than " +
                                  std::to_string(args.memory_bytes >> 20) + " MiB of memory");
}

StatusOr<TriangleMesh> ReadAndImport(const Arguments& args) {
  std::string bytes;
  if (!ReadAll(STDIN_FILENO, bytes)) return vscan::Internal("mesh importer: cannot read stdin");
  MaybeMisbehaveForTest();
  auto mesh = geometry::ImportMesh(bytes, args.format, args.metres_per_unit);
  if (!mesh.ok() && allocation_failed) return OutOfMemory(args);
  return mesh;
}

}  // namespace

// assimp 5.2 leaks a little on some error paths; a sanitizer build must not fail the import for it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

int main(int argc, char** argv) {
  std::optional<Arguments> args = Parse(argc, argv);
  if (!args) {
    std::cerr << "usage: vscan-mesh-import auto|ply|obj|stl METRES_PER_UNIT [MEMORY_BYTES [CPU_SECONDS]] "
                 "< mesh-file > result\n";
    return kUsageError;
  }
  if (Status limited = ApplyLimits(*args); !limited.ok()) return WriteResult(limited) ? 0 : 1;
  std::set_new_handler(OnAllocationFailure);
  try {
    return WriteResult(ReadAndImport(*args)) ? 0 : 1;
  } catch (const std::bad_alloc&) {
    return WriteResult(OutOfMemory(*args)) ? 0 : 1;
  }
}
