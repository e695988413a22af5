#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "scan/pixel_image_files.h"
#include "scan/scan_to_file.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/progress.h"
#include "session/text_format.h"
#include "vscan/common/chunk_limits.h"
#include "vscan/common/cloud_file_writer.h"
#include "vscan/common/point_chunks.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct ScanCommandArgs {
  ScanArgs scan;
  std::string output;
  bool organized = false;
  std::string images_dir;
};

// Client times from the call: to the first chunk (negative: none came) and to the last.
struct ClientTimes {
  double first_chunk_ms = -1;
  double total_ms = 0;
};

void PrintSummary(Context& ctx, const client::ScanResult& result, uint64_t points, const std::string& output,
                  const ClientTimes& times) {
  const auto& s = result.stats;
  ctx.Say("scan: " + std::to_string(points) + " points from " + std::to_string(s.rays()) + " rays (hit ratio " +
          Fixed(s.hit_ratio() * 100.0, 1) + "%)");
  if (points > 0) {
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
  add(s.rejected_dark(), "dark");
  add(s.rejected_saturated(), "saturated");
  add(s.rejected_interreflection(), "interreflection");
  if (!artefacts.empty()) ctx.Say("measurement: " + artefacts + " (" + Fixed(s.measurement_ms(), 1) + " ms)");
  ctx.Say("time: server scan " + Fixed(s.scan_ms(), 1) + " ms, server total " + Fixed(s.total_ms(), 1) +
          " ms, client total " + Fixed(times.total_ms, 1) + " ms" +
          (times.first_chunk_ms >= 0 ? " (first chunk " + Fixed(times.first_chunk_ms, 1) + " ms)" : ""));
  ctx.Say("wrote " + output);
}

int RunScan(Context& ctx, const ScanCommandArgs& args) {
  auto request = BuildScanRequest(args.scan);
  if (!request.ok()) return ctx.UsageError(request.status().message());
  if (const int rc = CheckOutput(ctx, args.output, args.organized); rc != kExitOk) return rc;
  if (!args.images_dir.empty()) {
    if (const int rc = PrepareImagesDir(ctx, args.images_dir); rc != kExitOk) return rc;
    request->set_pixel_images(true);
  }

  ScannedFile scanned;
  if (const int rc = ScanToFile(ctx, *request, args.output, &scanned, args.organized); rc != kExitOk) return rc;
  if (scanned.result.images) {
    if (const int rc = WritePixelImages(ctx, *scanned.result.images, args.images_dir); rc != kExitOk) return rc;
  }
  const client::ScanResult* result = &scanned.result;
  ClientTimes times{scanned.first_chunk_ms, scanned.total_ms};
  const uint64_t points = scanned.points;
  if (ctx.json()) {
    ctx.EmitJson("{\"header\":" + ToJson(result->header) + ",\"statistics\":" + ToJson(result->stats) +
                 ",\"output\":" + JsonQuote(args.output) + ",\"clientMs\":" + Fixed(times.total_ms, 3) +
                 (times.first_chunk_ms >= 0 ? ",\"firstChunkMs\":" + Fixed(times.first_chunk_ms, 3) : "") + "}");
  } else {
    PrintSummary(ctx, *result, points, args.output, times);
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
  cmd->add_option("--returned-light", s.returned_light,
                  "Light the scene with the sensor's emitter and each object's material: 'on', or "
                  "key=value,... of ReturnedLight (emitter_w_per_sr, exposure_s, aperture_diameter_m, full_well_e, "
                  "read_noise_e, min_snr, reference_e, indirect_samples, modulation_frequency_hz, interreflection_ratio, ...); "
                  "dark, saturated and (structured light with indirect_samples) interreflected rays are rejected");
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
  cmd->add_flag("--organized", args->organized,
                "Write the range image: an organised PCD of width x height points, NaN where no point came "
                "back, the sensor pose as VIEWPOINT (adds the pixel field)");
  cmd->add_option("--images", args->images_dir,
                  "Also write DIR/reasons.png (8-bit: each pixel's point status, 0 where nothing was hit) and "
                  "DIR/gray.png (16-bit grey image of the returned signal)");

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
