#include <chrono>
#include <cstdio>
#include <filesystem>

#include "args.h"
#include "commands.h"
#include "progress.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/cloud_io.h"

namespace vscan::cli {
namespace {

struct ScanCommandArgs {
  ScanArgs scan;
  std::string output;
};

// Checked before scanning so that a long scan is not thrown away at the end.
int CheckOutput(Context& ctx, const std::string& output) {
  std::string ext = std::filesystem::path(output).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".ply" && ext != ".pcd") return ctx.UsageError("-o: output must end in .ply or .pcd");
  std::filesystem::path dir = std::filesystem::path(output).parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    return ctx.LocalError(NotFound(output + ": directory " + dir.string() + " does not exist"));
  }
  return kExitOk;
}

std::string Fixed(double v, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
  return buf;
}

void PrintSummary(Context& ctx, const client::ScanResult& result, const std::string& output, double client_ms) {
  const auto& s = result.stats;
  ctx.Say("scan: " + std::to_string(result.cloud.size()) + " points from " + std::to_string(s.rays()) +
          " rays (hit ratio " + Fixed(s.hit_ratio() * 100.0, 1) + "%)");
  if (result.cloud.size() > 0) {
    ctx.Say("range: " + Fixed(s.min_range(), 4) + " .. " + Fixed(s.max_range(), 4) + " m");
  }
  std::string artefacts;
  const auto add = [&artefacts](uint64_t count, const char* what) {
    if (count > 0) artefacts += (artefacts.empty() ? "" : ", ") + std::to_string(count) + " " + what;
  };
  add(s.outliers(), "outliers");
  add(s.flying_pixels(), "flying pixels");
  add(s.rejected_out_of_range(), "out of range");
  add(s.rejected_unlit(), "unlit");
  add(s.rejected_shadowed(), "shadowed");
  add(s.rejected_grazing(), "grazing");
  add(s.rejected_dim(), "dim");
  if (!artefacts.empty()) ctx.Say("measurement: " + artefacts + " (" + Fixed(s.measurement_ms(), 1) + " ms)");
  ctx.Say("time: server scan " + Fixed(s.scan_ms(), 1) + " ms, server total " + Fixed(s.total_ms(), 1) +
          " ms, client total " + Fixed(client_ms, 1) + " ms");
  ctx.Say("wrote " + output);
}

int RunScan(Context& ctx, const ScanCommandArgs& args) {
  const auto request = BuildScanRequest(args.scan);
  if (!request.ok()) return ctx.UsageError(request.status().message());
  if (const int rc = CheckOutput(ctx, args.output); rc != kExitOk) return rc;

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar("scan", "points", !ctx.quiet() && !ctx.json());
  client::ScanCallbacks callbacks;
  callbacks.on_progress = [&bar](uint64_t done, uint64_t total) { bar.Update(done, total); };
  auto result = client->Scan(*request, callbacks);
  bar.Finish();
  if (!result.ok()) return ctx.ServerError(result.status());
  const double client_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const Status written = WriteCloud(result->cloud, args.output);
  if (!written.ok()) return ctx.LocalError(written);
  if (ctx.json()) {
    ctx.EmitJson("{\"header\":" + ToJson(result->header) + ",\"statistics\":" + ToJson(result->stats) +
                 ",\"output\":" + JsonQuote(args.output) + ",\"clientMs\":" + Fixed(client_ms, 3) + "}");
  } else {
    PrintSummary(ctx, *result, args.output, client_ms);
  }
  return kExitOk;
}

// Noise and artefacts (NoiseSpec), rejected rays and estimated normals.
void AddMeasurementOptions(CLI::App* cmd, ScanArgs& s) {
  cmd->add_option("--noise", s.noise_sigma, "Gaussian sigma a[,b[,c]] = a + b z + c z^2 in metres");
  cmd->add_flag("--along-ray", s.along_ray, "Noise along the ray instead of isotropic");
  cmd->add_option("--depth-step", s.depth_step_m, "Depth quantisation step in metres");
  cmd->add_option("--min-intensity", s.min_intensity, "Reject points dimmer than this");
  cmd->add_option("--outliers", s.outlier_rate, "Fraction of rays perturbed into outliers (0..1)");
  cmd->add_option("--outlier-angle", s.outlier_angle_deg, "Outlier rays tilt by up to this angle, degrees");
  cmd->add_option("--outlier-origin", s.outlier_origin_m, "Outlier ray origins move by up to this, metres");
  cmd->add_option("--grazing-limit", s.grazing_limit_deg, "Reject points seen at incidence above this, degrees");
  cmd->add_flag("--flying-pixels", s.flying_pixels, "Mixed points at depth edges");
  cmd->add_option("--flying-pixel-edge", s.flying_pixel_edge_m, "Depth jump that makes an edge, metres (0.02)");
  cmd->add_flag("--include-rejected", s.include_rejected,
                "Also return rejected rays at their clean positions (see the status field)");
  cmd->add_option("--estimate-normals", s.estimate_normals_k,
                  "Add k-nearest-neighbour normals of the measured cloud (optional k, default 16)")
      ->expected(0, 1)
      ->default_str("0");
  cmd->add_option("--normal-max-distance", s.normal_max_distance,
                  "Ignore neighbours farther than this for --estimate-normals, metres");
}

}  // namespace

void AddScanCommand(CLI::App& app, Context& ctx) {
  auto args = std::make_shared<ScanCommandArgs>();
  ScanArgs& s = args->scan;
  auto* cmd = app.add_subcommand("scan", "Scan a scene with a pinhole depth camera and write the cloud");
  cmd->add_option("SCENE", s.scene_id, "Scene id")->required();
  cmd->add_option("-o,--output", args->output, "Output file, .ply or .pcd")->required();

  cmd->add_option("--preset", s.preset, "Sensor preset name instead of the camera options below");
  cmd->add_option("--width", s.width, "Image width in pixels")->capture_default_str();
  cmd->add_option("--height", s.height, "Image height in pixels")->capture_default_str();
  auto* hfov = cmd->add_option("--hfov", s.hfov_deg, "Horizontal field of view in degrees (default 60)");
  auto* intrinsics = cmd->add_option("--intrinsics", s.intrinsics, "Pinhole intrinsics fx,fy,cx,cy in pixels");
  hfov->excludes(intrinsics);
  cmd->add_option("--near", s.near, "Near depth limit in metres")->capture_default_str();
  cmd->add_option("--far", s.far, "Far depth limit in metres")->capture_default_str();
  cmd->add_option("--lighting", s.lighting, "Camera light power,constant,linear,quadratic");

  auto* eye = cmd->add_option("--eye", s.eye, "Camera position x,y,z in metres");
  auto* target = cmd->add_option("--target", s.target, "Point the camera looks at x,y,z");
  auto* up = cmd->add_option("--up", s.up, "Rough up direction x,y,z")->capture_default_str();
  auto* matrix = cmd->add_option("--pose-matrix", s.pose_matrix, "world_from_sensor, 16 values row-major");
  matrix->excludes(eye)->excludes(target)->excludes(up);
  auto* mount = cmd->add_option("--mount", s.mount, "Hold the sensor on this robot mount instead of --eye/--target");
  cmd->add_option("--joints", s.joints, "The mounted robot's joint positions q1,q2,... (radians or metres)");
  cmd->add_flag("--encoder-noise", s.encoder_noise, "Perturb the joints by the mount's encoder sigma (--seed)");
  mount->excludes(eye)->excludes(target)->excludes(matrix);

  cmd->add_option("--frame", s.frame, "Coordinates of the output: world or sensor")->capture_default_str();
  cmd->add_option("--fields", s.fields,
                  "Comma-separated: position,normal,range,intensity,instance,pixel or all "
                  "(default: all but pixel); ground truth: clean,incidence,status or truth; "
                  "estimated-normal");
  cmd->add_option("--backend", s.backend, "raycast, depth or colour")->capture_default_str();
  cmd->add_option("--table-angle", s.table_angle_deg, "Rotary table angle for this scan only, degrees");
  cmd->add_option("--chunk-kib", s.chunk_kib,
                  "Size of one streamed chunk in KiB (" + std::to_string(kMinChunkBytes / 1024) + ".." +
                      std::to_string(kMaxChunkBytes / 1024) + ", default " +
                      std::to_string(kDefaultChunkBytes / 1024) + ")");
  cmd->add_option("--seed", s.seed, "Seed for noise")->capture_default_str();
  AddMeasurementOptions(cmd, s);
  OnRun(cmd, ctx, [&ctx, args] { return RunScan(ctx, *args); });
}

}  // namespace vscan::cli
