#include "bins/bin_scan.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include <google/protobuf/util/json_util.h>

#include "scan/pixel_image_files.h"
#include "scan/scan_to_file.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/text_format.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct BinScanArgs {
  std::string job_id;
  std::string output;
  bool organized = false;
  std::string preset = "ideal-vga";
  std::optional<double> distance;
  std::string fields = "all";
  std::string backend = "raycast";
  uint64_t seed = 0;
  std::optional<std::string> returned_light;
  std::string images_dir;
};

// The preset's camera (a structured-light preset's camera) as field-of-view tangents and depth range.
struct ViewCone {
  double tan_half_h = 0, tan_half_v = 0, near = 0.05, far = 10;
};

StatusOr<ViewCone> PresetCone(client::Client& client, const std::string& name) {
  ASSIGN_OR_RETURN(const auto presets, client.ListSensorPresets());
  for (const v1::SensorPreset& preset : presets) {
    if (preset.name() != name) continue;
    const v1::PinholeCamera& camera =
        preset.spec().has_structured_light() ? preset.spec().structured_light().camera() : preset.spec().pinhole();
    ViewCone cone;
    if (camera.has_intrinsics()) {
      cone.tan_half_h = camera.width() / (2 * camera.intrinsics().fx());
      cone.tan_half_v = camera.height() / (2 * camera.intrinsics().fy());
    } else {
      cone.tan_half_h = std::tan(camera.horizontal_fov_deg() * M_PI / 360);
      cone.tan_half_v = cone.tan_half_h * camera.height() / camera.width();
    }
    if (camera.near() > 0) cone.near = camera.near();
    if (camera.far() > 0) cone.far = camera.far();
    return cone;
  }
  return NotFound("--preset: no sensor preset '" + name + "' (see `vscan sensors`)");
}

// Distance from the sensor to the rim's plane at which an opening of half-extents (half_x, half_y)
// fills the view with a 10% margin.
double FitAboveRim(double half_x, double half_y, const ViewCone& cone) {
  return 1.1 * std::max(half_x / cone.tan_half_h, half_y / cone.tan_half_v);
}

// Height of the sensor above the bin's floor: the whole opening (walls included) in view at the
// rim, which is nearest the sensor and widest, and the rim no nearer than the near limit.
double FitHeight(const v1::BinBox& bin, const ViewCone& cone) {
  const double wall = bin.wall_thickness() > 0 ? bin.wall_thickness() : 0.01;
  const double half_x = 0.5 * bin.inner_size().x() + wall, half_y = 0.5 * bin.inner_size().y() + wall;
  const double rim = bin.inner_size().z();
  return rim + std::max(FitAboveRim(half_x, half_y, cone), 1.05 * cone.near);
}

// The same for a bin given as a mesh: its stored bounds at the bin's scale, in the bin frame, the
// sensor above the frame's origin; returns the height above that origin.
double FitHeight(const v1::Bounds& bounds, double scale, const ViewCone& cone) {
  const auto& lo = bounds.min();
  const auto& hi = bounds.max();
  const double half_x = scale * std::max(std::abs(lo.x()), std::abs(hi.x()));
  const double half_y = scale * std::max(std::abs(lo.y()), std::abs(hi.y()));
  const double rim = scale * hi.z();
  return rim + std::max(FitAboveRim(half_x, half_y, cone), 1.05 * cone.near);
}

std::string ObjectsJson(const v1::ScanStatistics& stats) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string out = "[";
  for (int i = 0; i < stats.objects_size(); ++i) {
    std::string object;
    if (!google::protobuf::util::MessageToJsonString(stats.objects(i), &object, options).ok()) object = "{}";
    out += (i ? ",\n  " : "\n  ") + object;
  }
  return out + "\n]";
}

Status WriteGroundTruth(const std::string& path, const BinScanArgs& args, const v1::Job& job,
                        const client::ScanResult& result, uint64_t points) {
  const v1::ScanHeader& header = result.header;
  std::string pose;
  for (int i = 0; i < header.sensor_pose().values_size(); ++i) {
    pose += (i ? "," : "") + std::to_string(header.sensor_pose().values(i));
  }
  const std::string json = "{\"job_id\":" + JsonQuote(job.job_id()) + ",\"scene_id\":" + JsonQuote(header.scene_id()) +
                           ",\"scene_revision\":" + std::to_string(header.scene_revision()) +
                           ",\"sensor\":" + JsonQuote(args.preset) + ",\"world_from_sensor\":[" + pose + "]" +
                           ",\"width\":" + std::to_string(header.width()) + ",\"height\":" +
                           std::to_string(header.height()) + ",\"cloud\":" + JsonQuote(args.output) +
                           ",\"points\":" + std::to_string(points) + ",\"objects\":" + ObjectsJson(result.stats) +
                           "}\n";
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << json;
  out.close();
  if (!out) return DataLoss(path + ": write failed");
  return Status::Ok();
}

int RunBinScan(Context& ctx, const BinScanArgs& args) {
  if (const int rc = CheckOutput(ctx, args.output, args.organized); rc != kExitOk) return rc;
  const auto fields = ParseFields(args.fields);
  if (!fields.ok()) return ctx.UsageError(fields.status().message());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->GetJob(args.job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  if (job->kind() != "bin_fill") return ctx.UsageError("JOB: job " + args.job_id + " is a " + job->kind() + " job, not a bin fill");
  if (job->state() != v1::JOB_STATE_SUCCEEDED) {
    return ctx.UsageError("JOB: bin fill " + args.job_id + " did not succeed; its scene holds no bin");
  }
  const v1::BinFillSpec& spec = job->bin_fill();
  const v1::BinBox& bin = spec.bin();
  const v1::Pose& bin_pose = spec.has_bin_mesh() ? spec.bin_mesh().pose() : bin.pose();
  const bool has_pose = spec.has_bin_mesh() ? spec.bin_mesh().has_pose() : bin.has_pose();
  const auto cone = PresetCone(*client, args.preset);
  if (!cone.ok()) return cone.status().code() == StatusCode::kNotFound ? ctx.UsageError(cone.status().message())
                                                                      : ctx.ServerError(cone.status());
  double height = 0;
  if (args.distance) {
    height = *args.distance;
  } else if (spec.has_bin_mesh()) {
    const auto mesh = client->GetMesh(spec.bin_mesh().mesh_id());
    if (!mesh.ok()) return ctx.ServerError(mesh.status());
    const double scale = spec.bin_mesh().scale() > 0 ? spec.bin_mesh().scale() : 1.0;
    height = FitHeight(mesh->bounds(), scale, *cone);
  } else {
    height = FitHeight(bin, *cone);
  }
  if (!(height > 0)) return ctx.UsageError("--distance: must be positive");
  Pose3 world_from_bin = Pose3::Identity();
  if (has_pose) {
    const auto pose = PoseFromProto(bin_pose, "bin.pose");
    if (!pose.ok()) return ctx.ServerError(pose.status());
    world_from_bin = *pose;
  }
  if (height > cone->far) {
    std::cerr << "warning: the bin's floor is " << Fixed(height, 3) << " m away, beyond the sensor's far limit of "
              << Fixed(cone->far, 3) << " m\n";
  }
  v1::ScanRequest request;
  request.set_scene_id(job->bin_fill().scene_id());
  request.mutable_sensor()->set_preset(args.preset);
  v1::LookAt* look = request.mutable_pose()->mutable_look_at();
  *look->mutable_eye() = ToProto(Eigen::Vector3d(world_from_bin * Eigen::Vector3d(0, 0, height)));
  *look->mutable_target() = ToProto(Eigen::Vector3d(world_from_bin.translation()));
  *look->mutable_up() = ToProto(Eigen::Vector3d(world_from_bin.linear() * Eigen::Vector3d::UnitY()));
  for (const v1::PointField field : *fields) request.add_fields(field);
  const auto backend = ParseBackend(args.backend);
  if (!backend.ok()) return ctx.UsageError(backend.status().message());
  request.set_backend(*backend);
  request.set_seed(args.seed);
  request.set_ground_truth(true);
  if (args.returned_light) {
    if (const Status filled = FillReturnedLight(*args.returned_light, request.mutable_returned_light()); !filled.ok()) {
      return ctx.UsageError(filled.message());
    }
  }

  if (!args.images_dir.empty()) {
    if (const int rc = PrepareImagesDir(ctx, args.images_dir); rc != kExitOk) return rc;
    request.set_pixel_images(true);
  }

  ScannedFile scanned;
  if (const int rc = ScanToFile(ctx, request, args.output, &scanned, args.organized); rc != kExitOk) return rc;
  if (scanned.result.images) {
    if (const int rc = WritePixelImages(ctx, *scanned.result.images, args.images_dir); rc != kExitOk) return rc;
  }
  const std::string truth_path = std::filesystem::path(args.output).replace_extension(".gt.json").string();
  if (const Status written = WriteGroundTruth(truth_path, args, *job, scanned.result, scanned.points); !written.ok()) {
    return ctx.LocalError(written);
  }
  const v1::ScanStatistics& stats = scanned.result.stats;
  if (ctx.json()) {
    ctx.EmitJson("{\"header\":" + ToJson(scanned.result.header) + ",\"statistics\":" + ToJson(stats) +
                 ",\"output\":" + JsonQuote(args.output) + ",\"groundTruth\":" + JsonQuote(truth_path) + "}");
    return kExitOk;
  }
  size_t hidden = 0;
  double sum = 0;
  for (const v1::ObjectTruth& object : stats.objects()) {
    sum += object.visible_fraction();
    hidden += object.visible_points() == 0;
  }
  ctx.Say("scan: " + std::to_string(scanned.points) + " points from " + std::to_string(stats.rays()) +
          " rays, the sensor " + Fixed(height, 3) + " m above the bin's floor");
  ctx.Say("ground truth: " + std::to_string(stats.objects_size()) + " objects in view, mean visible fraction " +
          Fixed(stats.objects_size() ? sum / stats.objects_size() : 0, 3) + ", " + std::to_string(hidden) +
          " wholly hidden");
  ctx.Say("wrote " + args.output + " and " + truth_path);
  return kExitOk;
}

}  // namespace

void AddBinScan(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<BinScanArgs>();
  auto* cmd = group.add_subcommand("scan", "Scan a filled bin from above; write the cloud and OUT.gt.json");
  cmd->add_option("JOB", args->job_id, "The bin fill's job id")->required();
  cmd->add_option("-o,--output", args->output, "Output cloud, .ply or .pcd (with instance ids)")->required();
  cmd->add_flag("--organized", args->organized, "Write the range image as an organised PCD, as for `vscan scan`");
  cmd->add_option("--preset", args->preset, "Sensor preset (see `vscan sensors`)")->capture_default_str();
  cmd->add_option("--distance", args->distance,
                  "Height of the sensor above the bin's floor, metres (default: the opening fills the view)");
  cmd->add_option("--fields", args->fields, "Point fields, as for `vscan scan`")->capture_default_str();
  cmd->add_option("--backend", args->backend, "raycast, depth or colour")->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed for the preset's noise")->capture_default_str();
  cmd->add_option("--returned-light", args->returned_light,
                  "Light the bin with the sensor's emitter and each part's material, as for `vscan scan`");
  cmd->add_option("--images", args->images_dir,
                  "Also write DIR/reasons.png and DIR/gray.png, the per-pixel images, as for `vscan scan`");
  OnRun(cmd, ctx, [&ctx, args] { return RunBinScan(ctx, *args); });
}

}  // namespace vscan::cli
