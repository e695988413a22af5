// vscan localize|score: the server's baseline localizer on a cloud, and BOP scores of pose
// estimates against a scan's ground truth.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>

#include <unistd.h>

#include "localization/localization_calls.h"
#include "localization/localize_progress_line.h"
#include "localization/pose_files.h"
#include "localization/score_gripper_args.h"
#include "session/args.h"
#include "session/commands.h"
#include "session/text_format.h"
#include "session/uploads.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

struct LocalizeArgs {
  std::string cloud;
  std::vector<std::string> meshes;  // one per part
  std::string units;
  std::vector<double> scales;           // none, one for every part, or one per part
  std::vector<uint32_t> max_instances;  // likewise
  double min_score = 0;
  std::string normals = "auto";
  std::string viewpoint;
  std::string output;
  bool progress = false;
  bool no_progress = false;
};

struct ScoreArgs {
  std::string truth;
  std::vector<std::string> estimates;
  std::vector<std::string> bop_objects;
  std::string symmetries;
  std::optional<double> add_threshold;
  std::optional<double> min_visible;
  ScoreGripperArgs gripper;
};

bool IsFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

StatusOr<v1::NormalSource> ParseNormalSource(const std::string& text) {
  if (text == "auto") return v1::NORMAL_SOURCE_UNSPECIFIED;
  if (text == "estimate") return v1::NORMAL_SOURCE_ESTIMATE;
  if (text == "cloud") return v1::NORMAL_SOURCE_CLOUD;
  return InvalidArgument("--normals", "auto, estimate or cloud, not '" + text + "'");
}

// A mesh id, or a file uploaded with its unit.
int ResolveMesh(Context& ctx, const LocalizeArgs& args, const std::string& mesh, std::string* mesh_id) {
  if (!IsFile(mesh)) {
    *mesh_id = mesh;
    return kExitOk;
  }
  if (args.units.empty()) return ctx.UsageError("--units: required with a mesh file (mm, cm, in or m)");
  const auto unit = ParseUnit(args.units);
  if (!unit.ok()) return ctx.UsageError(unit.status().message());
  client::MeshUploadOptions options;
  options.unit = *unit;
  v1::Mesh uploaded;
  if (const int rc = UploadMesh(ctx, mesh, options, &uploaded); rc != kExitOk) return rc;
  *mesh_id = uploaded.mesh_id();
  return kExitOk;
}

// The sensor's position from "<cloud>.gt.json" beside a cloud file, as `vscan bin scan` writes it.
std::optional<Eigen::Vector3d> SensorBeside(const std::string& cloud_file) {
  const std::string truth = std::filesystem::path(cloud_file).replace_extension(".gt.json").string();
  if (!IsFile(truth)) return std::nullopt;
  const auto file = ReadGroundTruth(truth);
  if (!file.ok() || !file->world_from_sensor) return std::nullopt;
  return file->world_from_sensor->translation();
}

// --scale and --max: none, one for every part, or one per --mesh in the same order.
template <typename T>
StatusOr<std::vector<T>> PerPart(const std::vector<T>& given, size_t parts, T fallback, const std::string& flag) {
  if (given.empty()) return std::vector<T>(parts, fallback);
  if (given.size() == 1) return std::vector<T>(parts, given[0]);
  if (given.size() == parts) return given;
  return InvalidArgument(flag, "given " + std::to_string(given.size()) + " times for " + std::to_string(parts) +
                                   " --mesh; give it once (every part) or once per --mesh, in the same order");
}

// One part: the single-part fields (any server understands them); several: the parts list.
void SetParts(v1::LocalizeRequest& request, const std::vector<std::string>& mesh_ids, const std::vector<double>& scales,
              const std::vector<uint32_t>& max_given) {
  if (mesh_ids.size() == 1) {
    request.set_mesh_id(mesh_ids[0]);
    request.set_scale(scales[0]);
    if (!max_given.empty()) request.mutable_options()->set_max_instances(max_given[0]);
    return;
  }
  if (max_given.size() == 1) request.mutable_options()->set_max_instances(max_given[0]);
  for (size_t i = 0; i < mesh_ids.size(); ++i) {
    v1::LocalizePart* part = request.add_parts();
    part->set_mesh_id(mesh_ids[i]);
    part->set_scale(scales[i]);
    if (max_given.size() == mesh_ids.size()) part->set_max_instances(max_given[i]);
  }
}

// Progress on stderr: with --progress, else when stderr is a terminal and the output is for people.
bool ShowProgress(const Context& ctx, const LocalizeArgs& args) {
  if (args.no_progress) return false;
  if (args.progress) return true;
  return !ctx.json() && !ctx.quiet() && ::isatty(STDERR_FILENO) != 0;
}

int RunLocalize(Context& ctx, const LocalizeArgs& args) {
  v1::LocalizeRequest request;
  const auto normals = ParseNormalSource(args.normals);
  if (!normals.ok()) return ctx.UsageError(normals.status().message());
  const auto scales = PerPart(args.scales, args.meshes.size(), 1.0, "--scale");
  if (!scales.ok()) return ctx.UsageError(scales.status().message());
  const auto max_instances = PerPart<uint32_t>(args.max_instances, args.meshes.size(), 0, "--max");
  if (!max_instances.ok()) return ctx.UsageError(max_instances.status().message());
  request.mutable_options()->set_normal_source(*normals);
  request.mutable_options()->set_min_score(args.min_score);
  std::optional<Eigen::Vector3d> viewpoint;
  if (!args.viewpoint.empty()) {
    const auto parsed = ParseVector3(args.viewpoint, "--viewpoint");
    if (!parsed.ok()) return ctx.UsageError(parsed.status().message());
    viewpoint = *parsed;
  }
  const bool cloud_file = IsFile(args.cloud);
  if (cloud_file && !viewpoint) viewpoint = SensorBeside(args.cloud);
  if (viewpoint) *request.mutable_options()->mutable_viewpoint() = ToProto(*viewpoint);
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  std::vector<std::string> mesh_ids(args.meshes.size());
  for (size_t i = 0; i < args.meshes.size(); ++i) {
    if (const int rc = ResolveMesh(ctx, args, args.meshes[i], &mesh_ids[i]); rc != kExitOk) return rc;
  }
  SetParts(request, mesh_ids, *scales, args.max_instances);

  // A file goes up as a stored cloud for the call and is deleted after it.
  std::string uploaded;
  if (cloud_file) {
    auto cloud = client->UploadCloudFile(args.cloud, {});
    if (!cloud.ok()) return ctx.ServerError(cloud.status());
    uploaded = cloud->cloud_id();
    request.set_cloud_id(uploaded);
  } else {
    request.set_cloud_id(args.cloud);
  }
  std::string names;
  for (const std::string& id : mesh_ids) names += (names.empty() ? "" : ", ") + id;
  ctx.Say("localizing " + names + " in " + (uploaded.empty() ? "cloud " + args.cloud : args.cloud) + " ...");
  StatusOr<v1::LocalizeResponse> response = Internal("not called");
  if (ShowProgress(ctx, args)) {
    LocalizeProgressLine line(::isatty(STDERR_FILENO) != 0);
    response = CallLocalizeWithProgress(*client, request, [&line](const v1::LocalizeProgress& p) { line.Update(p); });
  } else {
    response = CallLocalize(*client, request);
  }
  if (!uploaded.empty()) (void)client->DeleteCloud(uploaded);
  if (!response.ok()) return ctx.ServerError(response.status());

  EstimatesFile file;
  file.cloud = args.cloud;
  file.frame = response->frame() == v1::FRAME_SENSOR ? "sensor" : "world";
  file.localize_ms = response->localize_ms();
  for (size_t i = 0; i < mesh_ids.size(); ++i) {
    SearchedPart part{mesh_ids[i], (*scales)[i], (*max_instances)[i], 0, "", 0};
    if (static_cast<int>(i) < response->parts_size()) {
      part.found = response->parts(static_cast<int>(i)).found();
      part.stop_reason = response->parts(static_cast<int>(i)).stop_reason();
      part.voxel_size = response->parts(static_cast<int>(i)).voxel_size();
    }
    file.parts.push_back(std::move(part));
  }
  for (const v1::PoseEstimate& estimate : response->estimates()) {
    const auto pose = PoseFromProto(estimate.world_from_part(), "world_from_part");
    if (!pose.ok()) return ctx.ServerError(pose.status());
    if (estimate.part() >= mesh_ids.size()) {
      return ctx.ServerError(DataLoss("estimate of part " + std::to_string(estimate.part()) + ", not asked for"));
    }
    file.estimates.push_back({estimate.part(), mesh_ids[estimate.part()], (*scales)[estimate.part()], *pose,
                              estimate.score(), estimate.explained_points()});
  }
  std::ofstream out(args.output, std::ios::binary | std::ios::trunc);
  out << EstimatesJson(file);
  out.close();
  if (!out) return ctx.LocalError(DataLoss(args.output + ": write failed"));
  if (ctx.json()) {
    std::string ids;
    for (const std::string& id : mesh_ids) ids += (ids.empty() ? "" : ",") + JsonQuote(id);
    ctx.EmitJson("{\"response\":" + ToJson(*response) + ",\"meshId\":" + JsonQuote(mesh_ids[0]) + ",\"meshIds\":[" +
                 ids + "],\"output\":" + JsonQuote(args.output) + "}");
    return kExitOk;
  }
  ctx.Say("found " + std::to_string(response->estimates_size()) + " instances in " +
          std::to_string(response->points()) + " points (" + std::to_string(response->support_plane_points()) +
          " on the support plane) in " + Fixed(response->localize_ms() / 1000, 2) + " s");
  for (const SearchedPart& part : file.parts) {
    ctx.Say("  part " + std::to_string(&part - file.parts.data()) + " " + part.mesh_id + " at scale " +
            Fixed(part.scale, 4) + ": " + std::to_string(part.found) + " found; " + part.stop_reason);
  }
  for (int i = 0; i < response->estimates_size(); ++i) {
    const v1::PoseEstimate& e = response->estimates(i);
    const auto& v = e.world_from_part().values();
    ctx.Say("  " + std::to_string(i) + ": part " + std::to_string(e.part()) + ", score " + Fixed(e.score(), 3) + ", " +
            std::to_string(e.explained_points()) + " points, at (" + Fixed(v[3], 4) + ", " + Fixed(v[7], 4) + ", " +
            Fixed(v[11], 4) + ")");
  }
  ctx.Say("wrote " + args.output);
  return kExitOk;
}

// "N=MESH_ID" or "N=MESH_ID@SCALE".
StatusOr<std::map<int, PoseRow>> ParseBopObjects(const std::vector<std::string>& items) {
  std::map<int, PoseRow> out;
  for (const std::string& item : items) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos) return InvalidArgument("--bop-obj", "need N=MESH_ID[@SCALE], not '" + item + "'");
    PoseRow row;
    std::string mesh = item.substr(eq + 1);
    if (const size_t at = mesh.find('@'); at != std::string::npos) {
      const auto scale = ParseNumbers(mesh.substr(at + 1), 1, "--bop-obj");
      if (!scale.ok()) return scale.status();
      row.scale = (*scale)[0];
      mesh.resize(at);
    }
    row.mesh_id = mesh;
    try {
      out[std::stoi(item.substr(0, eq))] = row;
    } catch (const std::exception&) {
      return InvalidArgument("--bop-obj", "'" + item.substr(0, eq) + "' is not an object id");
    }
  }
  return out;
}

// The estimates of every file, and the parts the JSON files say were searched.
StatusOr<std::vector<PoseRow>> ReadAllEstimates(const ScoreArgs& args, const GroundTruthFile& truth,
                                                std::vector<SearchedPart>* searched) {
  ASSIGN_OR_RETURN(const auto bop_objects, ParseBopObjects(args.bop_objects));
  std::vector<PoseRow> rows;
  for (const std::string& path : args.estimates) {
    if (std::filesystem::path(path).extension() == ".csv") {
      if (!truth.world_from_sensor) return InvalidArgument(args.truth + ": world_from_sensor: required for BOP results");
      ASSIGN_OR_RETURN(auto read, ReadBopResults(path, *truth.world_from_sensor, bop_objects));
      rows.insert(rows.end(), read.begin(), read.end());
    } else {
      ASSIGN_OR_RETURN(auto read, ReadEstimates(path));
      rows.insert(rows.end(), read.estimates.begin(), read.estimates.end());
      searched->insert(searched->end(), read.parts.begin(), read.parts.end());
    }
  }
  return rows;
}

std::string Recall(bool has, double value) { return has ? Fixed(value, 3) : "-"; }

// grasp: the request had a gripper; its grasp success is printed beside the recalls.
void PrintScores(Context& ctx, const v1::ScorePosesResponse& response, bool grasp) {
  char line[200];
  std::snprintf(line, sizeof(line), "%-4s %-22s %9s %6s %9s %9s %8s %8s", "part", "mesh", "diam mm", "error",
                "instances", "estimates", "ADD(-S)", "MSSD AR");
  ctx.Say(std::string(line) + (grasp ? "    grasp" : ""));
  const auto grasp_column = [grasp](bool has, double value) {
    if (!grasp) return std::string();
    char cell[32];
    std::snprintf(cell, sizeof(cell), " %8s", Recall(has, value).c_str());
    return std::string(cell);
  };
  for (const v1::PartScore& part : response.parts()) {
    std::snprintf(line, sizeof(line), "%-4u %-22s %9.1f %6s %9llu %9llu %8s %8s", part.part(), part.mesh_id().c_str(),
                  part.diameter() * 1000, part.uses_add_s() ? "ADD-S" : "ADD",
                  static_cast<unsigned long long>(part.valid_instances()),
                  static_cast<unsigned long long>(part.estimates()),
                  Recall(part.has_add_recall(), part.add_recall()).c_str(),
                  Recall(part.has_mssd_average_recall(), part.mssd_average_recall()).c_str());
    ctx.Say(line + grasp_column(part.has_grasp_success(), part.grasp_success()));
  }
  std::snprintf(line, sizeof(line), "%-4s %-22s %9s %6s %9llu %9s %8s %8s", "all", "", "", "",
                static_cast<unsigned long long>(response.valid_instances()), "",
                Recall(response.has_add_recall(), response.add_recall()).c_str(),
                Recall(response.has_mssd_average_recall(), response.mssd_average_recall()).c_str());
  ctx.Say(line + grasp_column(response.has_grasp_success(), response.grasp_success()));
  ctx.Say("ADD(-S) correct below " + Fixed(response.add_threshold() * 100, 0) +
          "% of the diameter; instances seen less than the visibility cut are not counted");
  if (grasp) {
    ctx.Say("grasp: share of valid true instances whose estimate's best grasp from above holds the true part "
            "(unmatched instances count as failures)");
  }
}

int RunScore(Context& ctx, const ScoreArgs& args) {
  const auto gripper = BuildScoreGripper(args.gripper);
  if (!gripper.ok()) return ctx.UsageError(gripper.status().message());
  const auto truth = ReadGroundTruth(args.truth);
  if (!truth.ok()) {
    return truth.status().code() == StatusCode::kNotFound ? ctx.LocalError(truth.status())
                                                          : ctx.UsageError(truth.status().message());
  }
  std::vector<SearchedPart> searched;
  const auto rows = ReadAllEstimates(args, *truth, &searched);
  if (!rows.ok()) {
    return rows.status().code() == StatusCode::kNotFound ? ctx.LocalError(rows.status())
                                                         : ctx.UsageError(rows.status().message());
  }
  if (rows->empty() && searched.empty()) {
    return ctx.UsageError("--estimates: no estimates and no searched parts in the files given, so no part to score");
  }
  std::map<std::string, v1::PartSymmetry> symmetries;
  if (!args.symmetries.empty()) {
    auto read = ReadSymmetries(args.symmetries);
    if (!read.ok()) return ctx.UsageError(read.status().message());
    symmetries = std::move(*read);
  }
  v1::ScorePosesRequest request = BuildScoreRequest(*truth, *rows, symmetries, searched);
  if (args.add_threshold) request.mutable_options()->set_add_threshold(*args.add_threshold);
  if (args.min_visible) request.mutable_options()->set_min_visible_fraction(*args.min_visible);
  if (*gripper) *request.mutable_gripper() = **gripper;
  if (const auto up = ScoreUp(args.gripper)) *request.mutable_up() = *up;
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto response = CallScorePoses(*client, request);
  if (!response.ok()) return ctx.ServerError(response.status());
  if (ctx.json()) {
    ctx.EmitJson(ToJson(*response));
    return kExitOk;
  }
  PrintScores(ctx, *response, gripper->has_value());
  return kExitOk;
}

}  // namespace

void AddLocalizationCommands(CLI::App& group, Context& ctx) {
  auto largs = std::make_shared<LocalizeArgs>();
  auto* localize =
      group.add_subcommand("localize", "Find instances of one or several parts in a cloud with the server's localizer");
  localize->add_option("--cloud", largs->cloud, "A stored cloud's id, or a PLY/PCD file (world frame)")->required();
  localize
      ->add_option("--mesh", largs->meshes,
                   "A part: a mesh id, or a mesh file uploaded with --units (repeatable: several parts in one search)")
      ->required();
  localize->add_option("--units", largs->units, "Unit of the mesh files: mm, cm, in or m");
  localize->add_option("--scale", largs->scales,
                       "Scale on the mesh, as the bin plan gives it (1; once for every part, or once per --mesh)");
  localize->add_option("--max,--max-instances", largs->max_instances,
                       "At most this many instances (0: 10; once for every part, or once per --mesh)");
  localize->add_option("--min-score", largs->min_score, "Lowest score accepted (0: 0.08)")->capture_default_str();
  localize->add_option("--normals", largs->normals, "auto (the cloud's estimated normals, else estimated), estimate or cloud")
      ->capture_default_str();
  localize->add_option("--viewpoint", largs->viewpoint,
                       "x,y,z estimated normals face (default: the cloud's sensor, or the sensor of FILE.gt.json)");
  localize->add_option("-o,--out", largs->output, "Estimates file to write (JSON)")->required();
  localize->add_flag("--progress", largs->progress,
                     "Show the search's progress on stderr (default: only when stderr is a terminal)");
  localize->add_flag("--no-progress", largs->no_progress, "Never show progress");
  OnRun(localize, ctx, [&ctx, largs] { return RunLocalize(ctx, *largs); });

  auto sargs = std::make_shared<ScoreArgs>();
  auto* score = group.add_subcommand("score", "Score pose estimates against a scan's ground truth (BOP: ADD(-S), MSSD)");
  score->add_option("--truth", sargs->truth, "The scan's ground truth, SCAN.gt.json")->required();
  score->add_option("--estimates", sargs->estimates, "estimates.json from `localize`, or BOP results .csv (repeatable)")
      ->required();
  score->add_option("--bop-obj", sargs->bop_objects, "N=MESH_ID[@SCALE]: the mesh of BOP obj_id N (repeatable)");
  score->add_option("--symmetries", sargs->symmetries, "JSON of each symmetric mesh's axes and transforms");
  score->add_option("--add-threshold", sargs->add_threshold, "ADD(-S) threshold, fraction of the diameter (0.1)");
  score->add_option("--min-visible", sargs->min_visible, "Visibility cut (0.1, BOP's visib_gt_min)");
  AddScoreGripperOptions(score, sargs->gripper);
  OnRun(score, ctx, [&ctx, sargs] { return RunScore(ctx, *sargs); });
}

}  // namespace vscan::cli
