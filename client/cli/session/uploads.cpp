#include "session/uploads.h"

#include <filesystem>
#include <fstream>

#include "session/progress.h"

namespace vscan::cli {

int UploadMesh(Context& ctx, const std::string& file, const client::MeshUploadOptions& options, v1::Mesh* mesh) {
  if (!std::ifstream(file, std::ios::binary)) return ctx.LocalError(NotFound(file + ": cannot open for reading"));
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  ProgressBar bar("upload", "bytes", !ctx.quiet() && !ctx.json());
  auto uploaded =
      client->UploadMeshFile(file, options, [&](uint64_t done, uint64_t total) { bar.Update(done, total); });
  bar.Finish();
  if (!uploaded.ok()) {
    // The file was readable a moment ago, so a DATA_LOSS here is a local read failure.
    if (uploaded.status().code() == StatusCode::kDataLoss) return ctx.LocalError(uploaded.status());
    return ctx.ServerError(uploaded.status());
  }
  *mesh = std::move(uploaded).value();
  return kExitOk;
}

namespace {

// The client library names local files by their path below the bundle argument: unreadable ones
// (NOT_FOUND, DATA_LOSS) and links that leave the bundle (INVALID_ARGUMENT). Server messages start
// with a request field instead.
bool NamesLocalPath(const Status& status, const std::string& path) {
  const StatusCode code = status.code();
  if (code != StatusCode::kNotFound && code != StatusCode::kDataLoss && code != StatusCode::kInvalidArgument) {
    return false;
  }
  const std::string& message = status.message();
  if (!message.starts_with(path)) return false;
  const char next = message.size() > path.size() ? message[path.size()] : '\0';
  return next == ':' || next == '/' || path.ends_with('/');
}

}  // namespace

int UploadRobot(Context& ctx, const std::string& path, const client::RobotUploadOptions& options,
                const std::string& urdf_option, v1::Robot* robot) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return ctx.LocalError(NotFound(path + ": no such file or directory"));
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  auto uploaded = client->UploadRobotPath(path, options);
  if (!uploaded.ok()) {
    // Problems reading the bundle locally (links out of it too) are local errors; a missing URDF
    // choice is a usage error; the rest came from the server.
    const Status& status = uploaded.status();
    if (status.code() == StatusCode::kInvalidArgument && status.field() == "urdf_path") {
      return ctx.UsageError(urdf_option + ": " + std::string(status.text()));
    }
    return NamesLocalPath(status, path) ? ctx.LocalError(status) : ctx.ServerError(status);
  }
  *robot = std::move(uploaded).value();
  return kExitOk;
}

}  // namespace vscan::cli
