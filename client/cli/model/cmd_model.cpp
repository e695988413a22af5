// `vscan align|reconstruct|evaluate`: model jobs on stored clouds; `vscan model list|watch|cancel|
// delete|artifacts`: the model jobs themselves.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "campaign/campaign_report.h"
#include "job/job_commands.h"
#include "job/job_download.h"
#include "job/job_watch.h"
#include "model/model_args.h"
#include "model/model_fetch.h"
#include "model/model_report.h"
#include "session/commands.h"
#include "session/text_format.h"

namespace vscan::cli {
namespace {

struct ModelRunArgs {
  ModelArgs model;
  std::string out_dir;
  bool no_wait = false;
  bool validate = false;
};

std::string AlignmentsJson(const std::vector<v1::ScanAlignment>& alignments) {
  std::string out = "[";
  for (size_t i = 0; i < alignments.size(); ++i) out += (i ? "," : "") + ToJson(alignments[i]);
  return out + "]";
}

bool HasArtifact(const v1::Job& job, const std::string& name) {
  for (const auto& artifact : job.artifacts()) {
    if (artifact.name() == name) return true;
  }
  return false;
}

// Where the mesh went and how to look at it.
void SayWhereTheMeshIs(Context& ctx, const v1::Job& job, const std::string& out_dir) {
  if (!HasArtifact(job, "mesh.ply")) return;
  if (out_dir.empty()) {
    ctx.Say("mesh.ply is on the server; fetch it with `vscan model artifacts " + job.job_id() + " -o DIR`");
    return;
  }
  const std::string mesh = (std::filesystem::path(out_dir) / "mesh.ply").string();
  ctx.Say("mesh: " + mesh + "; look at it with `vscan render " + mesh + " -o mesh.png`");
}

// The summary of a model job's model.json once it has ended.
int FinishModelJob(Context& ctx, const WatchResult& watched, const std::string& out_dir,
                   const std::vector<std::string>& files, double seconds) {
  const v1::Job& job = watched.job;
  std::optional<v1::ModelReport> model;
  if (const int rc = FetchModelReport(ctx, job, &model); rc != kExitOk) return rc;
  if (ctx.json()) {
    ctx.EmitJson("{\"job\":" + ToJson(job) + ",\"alignments\":" + AlignmentsJson(watched.alignments) +
                 ",\"model\":" + (model ? ReportJson(*model) : "null") + ",\"outputDir\":" + JsonQuote(out_dir) +
                 ",\"files\":" + JsonStrings(files) + "}");
    return JobExitCode(job.state());
  }
  if (ctx.quiet()) {
    ctx.Print(job.job_id());
    return JobExitCode(job.state());
  }
  if (model) std::cout << FormatModelReport(*model);
  ctx.Say("job " + job.job_id() + " " + JobStateName(job.state()) + " in " + Format("%.1f s", seconds) +
          (job.message().empty() ? "" : "; " + job.message()));
  if (!out_dir.empty()) ctx.Say("files in " + out_dir);
  SayWhereTheMeshIs(ctx, job, out_dir);
  return JobExitCode(job.state());
}

JobFinish ModelFinish(Context& ctx) {
  return [&ctx](const WatchResult& watched, const std::string& out_dir, const std::vector<std::string>& files,
                double seconds) { return FinishModelJob(ctx, watched, out_dir, files, seconds); };
}

std::string Inputs(const v1::ModelSpec& spec) {
  if (!spec.campaign_job_id().empty()) return "the scans of campaign " + spec.campaign_job_id();
  return std::to_string(spec.cloud_ids_size()) + (spec.cloud_ids_size() == 1 ? " cloud" : " clouds");
}

int RunModel(Context& ctx, ModelCommand command, const ModelRunArgs& args) {
  const auto started = JobClock::now();
  const auto spec = BuildModelSpec(command, args.model);
  if (!spec.ok()) return ctx.UsageError(spec.status().message());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  if (args.validate) {
    if (const Status valid = client->ValidateModel(*spec); !valid.ok()) {
      return ctx.ServerError(NameOptionInError(command, valid));
    }
    if (ctx.json()) ctx.EmitJson("{\"valid\":true,\"spec\":" + ToJson(*spec) + "}");
    ctx.Done("the server accepts this model job on " + Inputs(*spec), "");
    return kExitOk;
  }
  const auto job = client->StartModel(*spec);
  if (!job.ok()) return ctx.ServerError(NameOptionInError(command, job.status()));
  if (SayStarted(ctx, *job, "started model job " + job->job_id() + " on " + Inputs(*spec), "", args.no_wait)) {
    return kExitOk;
  }
  return FollowJob(ctx, job->job_id(), args.out_dir, started, ModelFinish(ctx));
}

void AddInputOptions(CLI::App* cmd, ModelRunArgs& args) {
  ModelArgs& m = args.model;
  cmd->add_option("CLOUD_ID", m.cloud_ids, "Stored clouds, in this order (see `vscan cloud list`)");
  cmd->add_option("--campaign", m.campaign_job_id, "Every captured scan of this campaign job instead of CLOUD_ID...");
  cmd->add_option("--scene", m.scene_id,
                  "The scene whose objects are the ground truth and set the default crop (default: the clouds' "
                  "scene)");
  cmd->add_option("--crop", m.crop,
                  "Keep only points inside xmin,ymin,zmin,xmax,ymax,zmax (model frame, metres; default: a "
                  "cylinder round the ground truth above the table, when the scene is known)");
  cmd->add_option("--name", m.name, "Label shown in listings");
  cmd->add_option("-o,--out", args.out_dir,
                  "Download the artifacts (model.json, aligned.ply, ...) into this directory");
  cmd->add_flag("--no-wait", args.no_wait, "Start the job, print its id and return");
  cmd->add_flag("--validate", args.validate, "Ask the server to check the request; start nothing");
}

void AddAlignmentOptions(CLI::App* cmd, ModelCommand command, ModelArgs& m) {
  if (command != ModelCommand::kAlign) {
    cmd->add_flag("--skip-alignment", m.skip_alignment, "Take the clouds' poses as they are");
  }
  cmd->add_option("--initial", m.initial,
                  "Where alignment starts: known (the sensor poses; default when every cloud has one) or features");
  const char* voxel = command == ModelCommand::kAlign ? "--voxel,--align-voxel" : "--align-voxel";
  cmd->add_option(voxel, m.align_voxel, "Voxel the scans are thinned to for alignment, metres (default: from the "
                                        "object's size)");
  cmd->add_option("--max-distance", m.max_distance,
                  "Farthest pair ICP matches, metres (default: from the voxel size)");
  cmd->add_option("--min-fitness", m.min_fitness,
                  "A scan with a smaller share of matched points is left out as unaligned (default 0.3)");
  cmd->add_flag("--no-pose-graph", m.no_pose_graph,
                "Keep each scan's pose against the scans before it (no global pose graph)");
}

void AddReconstructionOptions(CLI::App* cmd, ModelCommand command, ModelArgs& m) {
  if (command == ModelCommand::kEvaluate) {
    cmd->add_flag("--reconstruct", m.reconstruct, "Reconstruct the surface too, and evaluate the mesh");
  }
  cmd->add_option("--method", m.method,
                  "tsdf or poisson (default: tsdf when every scan has a camera and pixel coordinates)");
  cmd->add_option("--voxel", m.reconstruction_voxel,
                  "TSDF voxel, or the voxel the union is evened out to for Poisson, metres (default: from the "
                  "object's size)");
  cmd->add_option("--depth", m.depth, "Poisson octree depth (default 8)");
}

void AddEvaluationOptions(CLI::App* cmd, ModelArgs& m) {
  cmd->add_option("--tau", m.tau,
                  "Distance threshold of precision, recall, F-score and coverage, metres (default: 1/200 of the "
                  "ground truth's bounding-box diagonal)");
  cmd->add_option("--next-best-views", m.next_best_views, "How many next best views to propose (default 3)");
  cmd->add_flag("--no-next-best-views", m.no_next_best_views, "Propose no next best views");
  cmd->add_option("--mount", m.mount_id,
                  "The robot mount that would carry the sensor for next best views (default: the campaign's)");
}

void AddModelCommand(CLI::App& app, Context& ctx, ModelCommand command) {
  static constexpr const char* kNames[] = {"align", "reconstruct", "evaluate"};
  static constexpr const char* kHelp[] = {
      "Align stored clouds or a campaign's scans into the model frame",
      "Align stored clouds and reconstruct their surface (TSDF or Poisson)",
      "Align (and reconstruct) stored clouds and score them against the true surface"};
  const auto index = static_cast<size_t>(command);
  auto args = std::make_shared<ModelRunArgs>();
  auto* cmd = app.add_subcommand(kNames[index], kHelp[index]);
  AddInputOptions(cmd, *args);
  AddAlignmentOptions(cmd, command, args->model);
  if (command != ModelCommand::kAlign) AddReconstructionOptions(cmd, command, args->model);
  if (command == ModelCommand::kEvaluate) AddEvaluationOptions(cmd, args->model);
  OnRun(cmd, ctx, [&ctx, command, args] { return RunModel(ctx, command, *args); });
}

}  // namespace

void AddModelCommands(CLI::App& app, Context& ctx) {
  AddModelCommand(app, ctx, ModelCommand::kAlign);
  AddModelCommand(app, ctx, ModelCommand::kReconstruct);
  AddModelCommand(app, ctx, ModelCommand::kEvaluate);
  auto* group = app.add_subcommand("model", "Model jobs (align, reconstruct, evaluate): follow, list, fetch");
  group->require_subcommand(1);
  AddJobList(*group, ctx, "model", "List model jobs");
  AddJobWatch(*group, ctx, "Follow a model job until it ends and print its report; exit 0 if it succeeded",
              ModelFinish(ctx), true);
  AddJobCancel(*group, ctx, "Cancel a model job");
  AddJobDelete(*group, ctx, "Delete an ended model job and its artifacts from the server");
  AddJobArtifacts(*group, ctx);
}

}  // namespace vscan::cli
