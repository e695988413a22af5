#pragma once
// The options of `vscan align|reconstruct|evaluate` and the ModelSpec they make. Every parser
// returns INVALID_ARGUMENT naming the option it rejects.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"
#include "vscan/v1/job.pb.h"
#include "vscan/v1/model.pb.h"

namespace vscan::cli {

// Which command the options came from: it decides what --voxel means and what runs.
enum class ModelCommand { kAlign, kReconstruct, kEvaluate };

// Empty strings / nullopt were not given.
struct ModelArgs {
  std::vector<std::string> cloud_ids;
  std::string campaign_job_id;
  std::string scene_id;
  std::string mount_id;
  std::string name;
  std::string crop;  // xmin,ymin,zmin,xmax,ymax,zmax
  // Alignment.
  bool skip_alignment = false;
  std::string initial;  // known or features
  std::optional<double> align_voxel;
  std::optional<double> max_distance;
  std::optional<double> min_fitness;
  bool no_pose_graph = false;
  // Reconstruction (always for `reconstruct`, with --reconstruct for `evaluate`).
  bool reconstruct = false;
  std::string method;  // tsdf or poisson
  std::optional<double> reconstruction_voxel;
  std::optional<uint32_t> depth;
  // Evaluation.
  std::optional<double> tau;
  std::optional<uint32_t> next_best_views;
  bool no_next_best_views = false;
};

StatusOr<v1::ModelSpec> BuildModelSpec(ModelCommand command, const ModelArgs& args);

// known or features.
StatusOr<v1::InitialPose> ParseInitialPose(const std::string& text);
// tsdf or poisson.
StatusOr<v1::ReconstructionMethod> ParseReconstructionMethod(const std::string& text);
// xmin,ymin,zmin,xmax,ymax,zmax in metres, each min below its max.
StatusOr<v1::Bounds> ParseCrop(const std::string& text);

// The option of command that sets a ModelSpec field the server names in its message
// ("spec.alignment.voxel_size: ..." -> "--voxel"); nullopt for a field no option sets.
std::optional<std::string> OptionForSpecField(ModelCommand command, std::string_view message);
// The server's verdict with the option it is about in front: "--voxel: spec.alignment.voxel_size: ...".
Status NameOptionInError(ModelCommand command, const Status& status);

}  // namespace vscan::cli
