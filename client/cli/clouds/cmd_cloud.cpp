// vscan cloud upload|list|get|delete|download: stored point clouds.

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>

#include "scan/pose_options.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/describe.h"
#include "session/progress.h"
#include "session/text_format.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct CloudUploadArgs {
  std::string file;
  std::string name;
  std::string format;
  std::string scene_id;
  std::string frame;
  std::string camera;
  PoseArgs pose;
};

StatusOr<client::CloudUploadOptions> UploadOptions(const CloudUploadArgs& args) {
  client::CloudUploadOptions options;
  options.name = args.name;
  options.scene_id = args.scene_id;
  if (!args.format.empty()) {
    ASSIGN_OR_RETURN(options.format, ParseCloudFormat(args.format));
  }
  if (!args.frame.empty()) {
    ASSIGN_OR_RETURN(options.frame, ParseFrame(args.frame));
  }
  if (!args.camera.empty()) {
    ASSIGN_OR_RETURN(options.camera, ParseCloudCamera(args.camera));
  }
  ASSIGN_OR_RETURN(const PoseParts parts, ParsePoseArgs(args.pose));
  if (!parts.empty()) options.sensor_pose = PoseToProto(ApplyPoseParts(parts, Pose3::Identity()));
  return options;
}

int RunCloudUpload(Context& ctx, const CloudUploadArgs& args) {
  const auto options = UploadOptions(args);
  if (!options.ok()) return ctx.UsageError(options.status().message());
  if (!std::ifstream(args.file, std::ios::binary)) {
    return ctx.LocalError(NotFound(args.file + ": cannot open for reading"));
  }
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  ProgressBar bar("upload", "bytes", !ctx.quiet() && !ctx.json());
  auto cloud =
      client->UploadCloudFile(args.file, *options, [&](uint64_t done, uint64_t total) { bar.Update(done, total); });
  bar.Finish();
  if (!cloud.ok()) {
    // The file was readable a moment ago, so a DATA_LOSS here is a local read failure.
    if (cloud.status().code() == StatusCode::kDataLoss) return ctx.LocalError(cloud.status());
    return ctx.ServerError(cloud.status());
  }
  if (ctx.json()) ctx.EmitJson(ToJson(*cloud));
  ctx.Done("uploaded cloud " + Describe(*cloud), cloud->cloud_id());
  return kExitOk;
}

void AddCloudUpload(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("upload", "Upload a point cloud (PLY binary or ASCII; PCD binary, ASCII or binary_compressed)");
  auto args = std::make_shared<CloudUploadArgs>();
  cmd->add_option("FILE", args->file, "Cloud file")->required();
  cmd->add_option("--name", args->name, "Cloud name (default: the file name)");
  cmd->add_option("--format", args->format, "ply or pcd (default: from the extension, else from the bytes)");
  cmd->add_option("--scene", args->scene_id, "The scene the cloud was scanned in");
  cmd->add_option("--frame", args->frame, "The frame of the points: world (default) or sensor");
  cmd->add_option("--camera", args->camera, "The scan's camera: width,height,fx,fy,cx,cy,near,far");
  AddPoseOptions(cmd, args->pose, "Sensor pose (world_from_sensor): ");
  OnRun(cmd, ctx, [&ctx, args] { return RunCloudUpload(ctx, *args); });
}

void AddCloudList(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("list", "List clouds");
  auto job = std::make_shared<std::string>();
  cmd->add_option("--job", *job, "Only the scans of this campaign job");
  OnRun(cmd, ctx, [&ctx, job]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto clouds = client->ListClouds(*job);
    if (!clouds.ok()) return ctx.ServerError(clouds.status());
    if (ctx.json()) {
      v1::ListCloudsResponse all;
      for (const auto& c : *clouds) *all.add_clouds() = c;
      ctx.EmitJson(ToJson(all));
      return kExitOk;
    }
    for (const auto& c : *clouds) ctx.Print(ctx.quiet() ? c.cloud_id() : Describe(c));
    return kExitOk;
  });
}

void AddCloudGet(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("get", "Show a cloud");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Cloud id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto cloud = client->GetCloud(*id);
    if (!cloud.ok()) return ctx.ServerError(cloud.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*cloud));
    } else {
      ctx.Print(Describe(*cloud) + "  sha256 " + cloud->sha256());
    }
    return kExitOk;
  });
}

void AddCloudDelete(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("delete", "Delete an uploaded cloud (a campaign's scans go with their job)");
  auto id = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Cloud id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto deleted = client->DeleteCloud(*id);
    if (!deleted.ok()) return ctx.ServerError(deleted.status());
    if (ctx.json()) {
      ctx.EmitJson("{\"cloudId\":" + JsonQuote(*id) + ",\"removedFiles\":" + std::to_string(deleted->removed_files()) +
                   ",\"removedBytes\":" + std::to_string(deleted->removed_bytes()) + "}");
    }
    ctx.Done("deleted cloud " + *id + " (" + std::to_string(deleted->removed_bytes()) + " bytes freed)", "");
    return kExitOk;
  });
}

// The stored PLY as it comes (.ply), or read and written again as PCD (.pcd).
int RunDownload(Context& ctx, const std::string& id, const std::string& output) {
  const std::string ext = LowerExtension(output);
  if (ext != ".ply" && ext != ".pcd") return ctx.UsageError("-o: output must end in .ply or .pcd");
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const std::string partial = output + ".part";
  std::ofstream out;
  std::string bytes;
  if (ext == ".ply") {
    out.open(partial, std::ios::binary | std::ios::trunc);
    if (!out) return ctx.LocalError(DataLoss(partial + ": cannot open for writing"));
  }
  ProgressBar bar("download", "bytes", !ctx.quiet() && !ctx.json());
  bool write_failed = false;
  const auto cloud = client->ReadCloud(
      id,
      [&](std::string_view chunk) -> Status {
        if (!out.is_open()) {
          bytes.append(chunk);
          return Status::Ok();
        }
        out.write(chunk.data(), static_cast<std::streamsize>(chunk.size()));
        write_failed = !out;
        return write_failed ? DataLoss(partial + ": write failed") : Status::Ok();
      },
      [&](uint64_t done, uint64_t total) { bar.Update(done, total); });
  bar.Finish();
  std::error_code ec;
  if (!cloud.ok()) {
    if (out.is_open()) std::filesystem::remove(partial, ec);
    return write_failed ? ctx.LocalError(cloud.status()) : ctx.ServerError(cloud.status());
  }
  if (out.is_open()) {
    out.close();
    if (!out) return ctx.LocalError(DataLoss(partial + ": write failed"));
    std::filesystem::rename(partial, output, ec);
    if (ec) return ctx.LocalError(DataLoss(output + ": cannot rename into place: " + ec.message()));
  } else {
    const auto points = ParsePly(bytes, "cloud '" + id + "'", UINT64_MAX);
    if (!points.ok()) return ctx.ServerError(points.status());
    if (const Status written = WritePcd(*points, output); !written.ok()) return ctx.LocalError(written);
  }
  if (ctx.json()) ctx.EmitJson(ToJson(*cloud));
  ctx.Done("wrote " + output + ": " + Describe(*cloud), output);
  return kExitOk;
}

void AddCloudDownload(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("download", "Write a cloud to a PLY or PCD file");
  auto id = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  cmd->add_option("ID", *id, "Cloud id")->required();
  cmd->add_option("-o,--output", *output, "Output file, .ply (as stored) or .pcd")->required();
  OnRun(cmd, ctx, [&ctx, id, output] { return RunDownload(ctx, *id, *output); });
}

}  // namespace

void AddCloudCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("cloud", "Upload, list, show, download and delete stored point clouds");
  group->require_subcommand(1);
  AddCloudUpload(*group, ctx);
  AddCloudList(*group, ctx);
  AddCloudGet(*group, ctx);
  AddCloudDelete(*group, ctx);
  AddCloudDownload(*group, ctx);
}

}  // namespace vscan::cli
