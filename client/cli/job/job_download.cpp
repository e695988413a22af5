#include "job/job_download.h"

#include <filesystem>
#include <fstream>

#include "session/progress.h"

namespace vscan::cli {
namespace {

// The artifact's name unless it could leave the directory.
std::string SafeName(const v1::Artifact& artifact) {
  const std::string& name = artifact.name();
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
      name.find('\\') != std::string::npos) {
    return artifact.artifact_id();
  }
  return name;
}

Status WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text << '\n';
  out.close();
  if (!out) return DataLoss(path.string() + ": cannot write");
  return Status::Ok();
}

}  // namespace

int DownloadArtifacts(Context& ctx, const v1::Job& job, const std::string& dir, std::vector<std::string>* files) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return ctx.LocalError(DataLoss(dir + ": cannot create directory: " + ec.message()));

  uint64_t total = 0;
  for (const auto& artifact : job.artifacts()) total += artifact.size_bytes();
  ProgressBar bar("download", "bytes", !ctx.quiet() && !ctx.json());
  uint64_t before = 0;
  for (const auto& artifact : job.artifacts()) {
    const std::filesystem::path path = std::filesystem::path(dir) / SafeName(artifact);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) return ctx.LocalError(DataLoss(path.string() + ": cannot open for writing"));
    bool write_failed = false;
    const auto read = client->ReadArtifact(
        job.job_id(), artifact.artifact_id(),
        [&](std::string_view bytes) -> Status {
          out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
          write_failed = !out;
          if (write_failed) return DataLoss(path.string() + ": write failed");
          return Status::Ok();
        },
        [&](uint64_t done, uint64_t) { bar.Update(before + done, total); });
    out.close();
    if (!read.ok()) {
      bar.Finish();
      return write_failed ? ctx.LocalError(read.status()) : ctx.ServerError(read.status());
    }
    if (!out) return ctx.LocalError(DataLoss(path.string() + ": write failed"));
    before += artifact.size_bytes();
    files->push_back(path.string());
  }
  bar.Finish();
  const std::filesystem::path job_json = std::filesystem::path(dir) / "job.json";
  if (const Status written = WriteText(job_json, ToJson(job)); !written.ok()) return ctx.LocalError(written);
  files->push_back(job_json.string());
  return kExitOk;
}

}  // namespace vscan::cli
