#include "geometry/sandboxed_import.h"

#include <sys/wait.h>

#include <cstdio>
#include <vector>

#include "geometry/child_process.h"
#include "geometry/import_protocol.h"

namespace vscan::geometry {
namespace {

// Vertices are at most three per triangle; see EncodeMesh for the sizes.
constexpr size_t kMaxResultBytes = kImportResultHeaderSize + 24 + 48 * kMaxImportTriangles;

std::string HexDouble(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

std::string Seconds(std::chrono::milliseconds duration) {
  const auto ms = duration.count();
  if (ms % 1000 == 0) return std::to_string(ms / 1000);
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", static_cast<double>(ms) / 1000.0);
  return text;
}

// A CPU limit a little past the wall-clock timeout: it only matters if this process is gone.
uint64_t CpuSeconds(std::chrono::milliseconds timeout) {
  return static_cast<uint64_t>(std::chrono::ceil<std::chrono::seconds>(timeout).count()) + 1;
}

}  // namespace

StatusOr<TriangleMesh> ImportMeshIsolated(std::string_view bytes, MeshFileFormat format, double metres_per_unit,
                                          const ImportSandbox& options) {
  const std::vector<std::string> argv = {options.helper_path, std::string(MeshFileFormatName(format)),
                                         HexDouble(metres_per_unit), std::to_string(options.memory_limit_bytes),
                                         std::to_string(CpuSeconds(options.timeout))};
  auto run = RunChild(argv, bytes, options.timeout, kMaxResultBytes);
  if (!run.ok()) return Status(run.status().code(), "mesh importer: " + run.status().message());
  const ChildOutcome& outcome = *run;
  if (outcome.timed_out) {
    return InvalidArgument("mesh data: import did not finish within " + Seconds(options.timeout) + " s");
  }
  if (outcome.output_too_large) {
    return Internal("mesh importer: result exceeds " + std::to_string(kMaxResultBytes) + " bytes");
  }
  if (WIFSIGNALED(outcome.wait_status)) {
    return InvalidArgument("mesh data: the file could not be parsed (importer stopped by signal " +
                           std::to_string(WTERMSIG(outcome.wait_status)) + ")");
  }
  if (WIFEXITED(outcome.wait_status) && WEXITSTATUS(outcome.wait_status) != 0) {
    return InvalidArgument("mesh data: the file could not be parsed (importer exited with status " +
                           std::to_string(WEXITSTATUS(outcome.wait_status)) + ")");
  }
  return ParseImportResult(outcome.output);
}

}  // namespace vscan::geometry
