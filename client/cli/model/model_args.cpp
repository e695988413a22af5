#include "model/model_args.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "session/args.h"

#include "session/text_format.h"

namespace vscan::cli {
namespace {

// The voxel of the stage a command is named after: alignment for `align`, reconstruction otherwise.
const char* AlignVoxelOption(ModelCommand command) {
  return command == ModelCommand::kAlign ? "--voxel" : "--align-voxel";
}

Status CheckLength(const std::optional<double>& value, const char* option) {
  if (value && !(std::isfinite(*value) && *value >= 0)) {
    return InvalidArgument(option, "must be a length in metres, 0 or more (0: the server picks it)");
  }
  return Status::Ok();
}

Status CheckAlignment(ModelCommand command, const ModelArgs& args) {
  RETURN_IF_ERROR(CheckLength(args.align_voxel, AlignVoxelOption(command)));
  RETURN_IF_ERROR(CheckLength(args.max_distance, "--max-distance"));
  if (args.min_fitness && !(*args.min_fitness >= 0 && *args.min_fitness <= 1)) {
    return InvalidArgument("--min-fitness", "must be a share between 0 and 1 (0: the server default 0.3)");
  }
  if (!args.skip_alignment) return Status::Ok();
  const std::pair<bool, const char*> alignment_options[] = {
      {!args.initial.empty(), "--initial"},
      {args.align_voxel.has_value(), AlignVoxelOption(command)},
      {args.max_distance.has_value(), "--max-distance"},
      {args.min_fitness.has_value(), "--min-fitness"},
      {args.no_pose_graph, "--no-pose-graph"}};
  for (const auto& [given, option] : alignment_options) {
    if (given) return InvalidArgument(option, "is an alignment option; --skip-alignment skips the alignment");
  }
  return Status::Ok();
}

Status CheckReconstruction(bool reconstruct, const ModelArgs& args) {
  RETURN_IF_ERROR(CheckLength(args.reconstruction_voxel, "--voxel"));
  if (reconstruct) return Status::Ok();
  const std::pair<bool, const char*> reconstruction_options[] = {{!args.method.empty(), "--method"},
                                                                 {args.reconstruction_voxel.has_value(), "--voxel"},
                                                                 {args.depth.has_value(), "--depth"}};
  for (const auto& [given, option] : reconstruction_options) {
    if (given) return InvalidArgument(option, "needs --reconstruct");
  }
  return Status::Ok();
}

Status CheckEvaluation(const ModelArgs& args) {
  RETURN_IF_ERROR(CheckLength(args.tau, "--tau"));
  if (args.no_next_best_views && args.next_best_views) {
    return InvalidArgument("--no-next-best-views", "conflicts with --next-best-views");
  }
  return Status::Ok();
}

// The spec fields an option sets; "" in option stands for the command's alignment voxel option.
struct FieldOption {
  std::string_view field;
  std::string_view option;
};

constexpr FieldOption kFieldOptions[] = {
    {"spec.cloud_ids", "CLOUD_ID"},
    {"spec.campaign_job_id", "--campaign"},
    {"spec.skip_alignment", "--skip-alignment"},
    {"spec.alignment.initial_pose", "--initial"},
    {"spec.alignment.voxel_size", ""},
    {"spec.alignment.max_correspondence_distance", "--max-distance"},
    {"spec.alignment.min_fitness", "--min-fitness"},
    {"spec.alignment.skip_pose_graph", "--no-pose-graph"},
    {"spec.reconstruct", "--reconstruct"},
    {"spec.reconstruction.method", "--method"},
    {"spec.reconstruction.voxel_size", "--voxel"},
    {"spec.reconstruction.poisson_depth", "--depth"},
    {"spec.evaluation.tau", "--tau"},
    {"spec.evaluation.next_best_views", "--next-best-views"},
    {"spec.evaluation.skip_next_best_views", "--no-next-best-views"},
    {"spec.scene_id", "--scene"},
    {"spec.mount_id", "--mount"},
    {"spec.crop", "--crop"},
    {"spec.name", "--name"},
};

}  // namespace

StatusOr<v1::InitialPose> ParseInitialPose(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "known") return v1::INITIAL_POSE_KNOWN;
  if (t == "features") return v1::INITIAL_POSE_FEATURES;
  return InvalidArgument("--initial", "unknown initial pose '" + text + "' (known, features)");
}

StatusOr<v1::ReconstructionMethod> ParseReconstructionMethod(const std::string& text) {
  const std::string t = Lower(text);
  if (t == "tsdf") return v1::RECONSTRUCTION_METHOD_TSDF;
  if (t == "poisson") return v1::RECONSTRUCTION_METHOD_POISSON;
  return InvalidArgument("--method", "unknown reconstruction method '" + text + "' (tsdf, poisson)");
}

StatusOr<v1::Bounds> ParseCrop(const std::string& text) {
  ASSIGN_OR_RETURN(const std::vector<double> v, ParseNumbers(text, 6, "--crop"));
  for (int i = 0; i < 3; ++i) {
    if (!(v[i] < v[i + 3])) {
      return InvalidArgument("--crop", std::string("min ") + "xyz"[i] + " must be below max " + "xyz"[i] +
                                           " (xmin,ymin,zmin,xmax,ymax,zmax)");
    }
  }
  v1::Bounds bounds;
  bounds.mutable_min()->set_x(v[0]);
  bounds.mutable_min()->set_y(v[1]);
  bounds.mutable_min()->set_z(v[2]);
  bounds.mutable_max()->set_x(v[3]);
  bounds.mutable_max()->set_y(v[4]);
  bounds.mutable_max()->set_z(v[5]);
  return bounds;
}

StatusOr<v1::ModelSpec> BuildModelSpec(ModelCommand command, const ModelArgs& args) {
  if (args.cloud_ids.empty() == args.campaign_job_id.empty()) {
    return InvalidArgument("CLOUD_ID", args.cloud_ids.empty()
                                           ? "give the clouds to work on, or --campaign JOB_ID for a campaign's scans"
                                           : "give clouds or --campaign, not both");
  }
  const bool reconstruct = command == ModelCommand::kReconstruct || args.reconstruct;
  RETURN_IF_ERROR(CheckAlignment(command, args));
  RETURN_IF_ERROR(CheckReconstruction(reconstruct, args));
  RETURN_IF_ERROR(CheckEvaluation(args));

  v1::ModelSpec spec;
  for (const std::string& id : args.cloud_ids) spec.add_cloud_ids(id);
  spec.set_campaign_job_id(args.campaign_job_id);
  spec.set_scene_id(args.scene_id);
  spec.set_mount_id(args.mount_id);
  spec.set_name(args.name);
  if (!args.crop.empty()) {
    ASSIGN_OR_RETURN(*spec.mutable_crop(), ParseCrop(args.crop));
  }

  spec.set_skip_alignment(args.skip_alignment);
  v1::AlignmentOptions* alignment = spec.mutable_alignment();
  if (!args.initial.empty()) {
    ASSIGN_OR_RETURN(const v1::InitialPose initial, ParseInitialPose(args.initial));
    alignment->set_initial_pose(initial);
  }
  alignment->set_voxel_size(args.align_voxel.value_or(0.0));
  alignment->set_max_correspondence_distance(args.max_distance.value_or(0.0));
  alignment->set_min_fitness(args.min_fitness.value_or(0.0));
  alignment->set_skip_pose_graph(args.no_pose_graph);

  spec.set_reconstruct(reconstruct);
  if (reconstruct) {
    v1::ReconstructionOptions* reconstruction = spec.mutable_reconstruction();
    if (!args.method.empty()) {
      ASSIGN_OR_RETURN(const v1::ReconstructionMethod method, ParseReconstructionMethod(args.method));
      reconstruction->set_method(method);
    }
    reconstruction->set_voxel_size(args.reconstruction_voxel.value_or(0.0));
    reconstruction->set_poisson_depth(args.depth.value_or(0));
  }

  spec.set_evaluate(command == ModelCommand::kEvaluate);
  if (spec.evaluate()) {
    v1::EvaluationOptions* evaluation = spec.mutable_evaluation();
    evaluation->set_tau(args.tau.value_or(0.0));
    evaluation->set_next_best_views(args.next_best_views.value_or(0));
    evaluation->set_skip_next_best_views(args.no_next_best_views);
  }
  return spec;
}

std::optional<std::string> OptionForSpecField(ModelCommand command, std::string_view message) {
  size_t end = 0;
  while (end < message.size() && message[end] != ':' && message[end] != ' ') ++end;
  const std::string_view field = message.substr(0, end);
  for (const FieldOption& known : kFieldOptions) {
    if (!field.starts_with(known.field)) continue;
    const std::string_view rest = field.substr(known.field.size());
    if (!rest.empty() && rest.front() != '[' && rest.front() != '.') continue;
    const std::string option = known.option.empty() ? AlignVoxelOption(command) : std::string(known.option);
    // A cloud's index stays: "CLOUD_ID[3]".
    return rest.starts_with('[') ? option + std::string(rest.substr(0, rest.find(']') + 1)) : option;
  }
  return std::nullopt;
}

Status NameOptionInError(ModelCommand command, const Status& status) {
  if (status.ok() || !NamesAField(status.code())) return status;
  const std::string& message = status.message();
  const auto option = OptionForSpecField(command, message);
  if (!option) return status;
  return Status(status.code(), *option + ": " + message);
}

}  // namespace vscan::cli
