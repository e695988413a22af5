// `vscan pick run|watch|resume|get|list|cancel|delete|artifacts`: picking jobs, a mounted robot emptying the
// bin a bin fill left in its scene (JobService.StartPicking).

#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "campaign/campaign_report.h"
#include "job/job_commands.h"
#include "job/job_watch.h"
#include "model/model_report.h"
#include "picking/cmd_pick_estimates.h"
#include "picking/gripper_args.h"
#include "picking/picking_job_report.h"
#include "session/commands.h"

namespace vscan::cli {
namespace {

struct PickRunArgs {
  std::string bin_job_id;
  std::string mount_id;
  GripperArgs gripper;
  bool truth = false;
  std::string perception;
  std::optional<double> estimates_timeout_s;
  std::optional<uint32_t> width;
  std::optional<uint32_t> height;
  std::optional<double> hfov_deg;
  std::optional<uint32_t> max_steps;
  std::optional<uint32_t> max_failures;
  std::optional<uint64_t> seed;
  std::optional<uint32_t> max_grasps;
  std::optional<double> body_length;
  std::string name;
  std::string out_dir;
  bool validate_only = false;
  bool watch = false;
};

// The end of `run --watch` and `watch`: the summary of picking.json (--json: picking.json itself),
// the job's exit code.
int FinishPicking(Context& ctx, const v1::Job& job, const std::string& out_dir) {
  std::optional<v1::PickingReport> report;
  if (const int rc = FetchPickingReport(ctx, job, &report); rc != kExitOk) return rc;
  if (ctx.json()) {
    if (report) ctx.EmitJson(ReportJson(*report));
    return JobExitCode(job.state());
  }
  if (!ctx.quiet()) {
    std::cout << "job " << job.job_id() << " " << JobStateName(job.state()) << ": " << job.message() << '\n';
    if (report) std::cout << FormatPickingReport(*report);
    if (!out_dir.empty()) std::cout << "files in " << out_dir << '\n';
  } else {
    ctx.Print(job.job_id());
  }
  return JobExitCode(job.state());
}

JobFinish PickFinish(Context& ctx) {
  return [&ctx](const WatchResult& watched, const std::string& out_dir, const std::vector<std::string>&, double) {
    return FinishPicking(ctx, watched.job, out_dir);
  };
}

StatusOr<v1::PickingSpec> BuildPickingSpec(const PickRunArgs& args) {
  v1::PickingSpec spec;
  spec.set_name(args.name);
  spec.set_bin_job_id(args.bin_job_id);
  spec.set_mount_id(args.mount_id);
  ASSIGN_OR_RETURN(*spec.mutable_gripper(), BuildGripper(args.gripper));
  if (args.truth) spec.set_perception(v1::PICKING_PERCEPTION_TRUTH);
  if (args.perception == "truth") spec.set_perception(v1::PICKING_PERCEPTION_TRUTH);
  if (args.perception == "client") spec.set_perception(v1::PICKING_PERCEPTION_CLIENT);
  if (!args.perception.empty() && args.perception != "baseline" && args.perception != "truth" &&
      args.perception != "client") {
    return InvalidArgument("--perception: baseline, truth or client");
  }
  if (args.truth && !args.perception.empty() && args.perception != "truth") {
    return InvalidArgument("--truth: contradicts --perception " + args.perception);
  }
  if (args.estimates_timeout_s) spec.set_estimates_timeout_s(*args.estimates_timeout_s);
  if (args.width) spec.set_width(*args.width);
  if (args.height) spec.set_height(*args.height);
  if (args.hfov_deg) spec.set_horizontal_fov_deg(*args.hfov_deg);
  if (args.max_steps) spec.set_max_steps(*args.max_steps);
  if (args.max_failures) spec.set_max_failures_in_a_row(*args.max_failures);
  if (args.seed) spec.set_seed(*args.seed);
  if (args.max_grasps) spec.mutable_grasp_options()->set_max_grasps(*args.max_grasps);
  if (args.body_length) spec.mutable_pick_options()->set_body_length(*args.body_length);
  return spec;
}

std::string PerceptionWords(const v1::PickingSpec& spec) {
  switch (spec.perception()) {
    case v1::PICKING_PERCEPTION_TRUTH: return "true poses";
    case v1::PICKING_PERCEPTION_CLIENT: return "your estimates: vscan pick estimates JOB --step N FILE";
    default: return "scan and baseline localizer";
  }
}

int RunPick(Context& ctx, const PickRunArgs& args) {
  const auto started = JobClock::now();
  const auto spec = BuildPickingSpec(args);
  if (!spec.ok()) return ctx.UsageError(spec.status().message());
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  if (args.validate_only) {
    if (const Status status = client->ValidatePicking(*spec); !status.ok()) return ctx.ServerError(status);
    ctx.Done("the server accepts this picking job", "");
    return kExitOk;
  }
  const auto job = client->StartPicking(*spec);
  if (!job.ok()) return ctx.ServerError(job.status());
  const std::string line = "started picking job " + job->job_id() + " (" + std::to_string(job->steps_total()) +
                           " parts in the bin of " + args.bin_job_id + ", " +
                           PerceptionWords(*spec) + ")";
  if (SayStarted(ctx, *job, line, "", !args.watch && args.out_dir.empty())) return kExitOk;
  return FollowJob(ctx, job->job_id(), args.out_dir, started, PickFinish(ctx));
}

void AddPickRun(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<PickRunArgs>();
  auto* cmd = group.add_subcommand("run", "Start a picking job: the mount's robot empties a bin fill's bin");
  cmd->add_option("--bin-job", args->bin_job_id, "A succeeded bin fill job; its scene holds the pile")->required();
  cmd->add_option("--mount", args->mount_id, "A mount in that scene; its tool frame is the gripper's tool centre point")
      ->required();
  AddGripperOptions(cmd, args->gripper);
  cmd->add_flag("--truth", args->truth, "Plan on the parts' true poses instead of a scan and the baseline localizer");
  cmd->add_option("--perception", args->perception,
                  "baseline (a scan and vscan's localizer), truth (--truth) or client (each step waits for "
                  "`vscan pick estimates`)");
  cmd->add_option("--estimates-timeout", args->estimates_timeout_s,
                  "With --perception client: how long a step waits for its estimates, s (600)");
  cmd->add_option("--width", args->width, "Scan image width, pixels (640)");
  cmd->add_option("--height", args->height, "Scan image height, pixels (512)");
  cmd->add_option("--hfov", args->hfov_deg, "Scan camera's horizontal field of view, degrees (50)");
  cmd->add_option("--max-steps", args->max_steps, "At most this many steps (500)");
  cmd->add_option("--max-failures", args->max_failures, "Give up after this many failed picks in a row (3)");
  cmd->add_option("--seed", args->seed, "Seeds the scans and the grasps (1)");
  cmd->add_option("--max-grasps", args->max_grasps, "At most this many grasps per part, best first (100)");
  cmd->add_option("--body-length", args->body_length,
                  "The gripper's body behind the tool centre point, m (the mount's tool offset length)");
  cmd->add_option("--name", args->name, "The job's name");
  cmd->add_option("-o,--out", args->out_dir, "Follow the job, then download its artifacts into this directory");
  cmd->add_flag("--validate-only", args->validate_only, "Ask the server to check the job; start nothing");
  cmd->add_flag("--watch", args->watch, "Follow the job until it ends and print its summary");
  OnRun(cmd, ctx, [&ctx, args] { return RunPick(ctx, *args); });
}

struct PickResumeArgs {
  std::string job_id;
  std::string out_dir;
  bool watch = false;
};

int ResumePick(Context& ctx, const PickResumeArgs& args) {
  const auto started = JobClock::now();
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->ResumeJob(args.job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  const std::string line = "resumed picking job " + job->job_id() + " on the pile its scene holds";
  if (SayStarted(ctx, *job, line, "", !args.watch && args.out_dir.empty())) return kExitOk;
  return FollowJob(ctx, job->job_id(), args.out_dir, started, PickFinish(ctx));
}

void AddPickResume(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<PickResumeArgs>();
  auto* cmd = group.add_subcommand(
      "resume", "Run an interrupted, cancelled or failed picking job on from the pile its scene holds");
  cmd->add_option("JOB", args->job_id, "Job id")->required();
  cmd->add_flag("--watch", args->watch, "Follow the job until it ends and print its summary");
  cmd->add_option("-o,--out", args->out_dir, "Follow the job, then download its artifacts into this directory");
  OnRun(cmd, ctx, [&ctx, args] { return ResumePick(ctx, *args); });
}

void AddPickGet(CLI::App& group, Context& ctx) {
  AddJobGet(group, ctx, "Show a picking job: state, message, the summary of its picking.json",
            [&ctx](const v1::Job& job) -> int {
              std::optional<v1::PickingReport> report;
              if (const int rc = FetchPickingReport(ctx, job, &report); rc != kExitOk) return rc;
              if (report && !ctx.quiet()) std::cout << FormatPickingReport(*report);
              if (job.has_awaiting_estimates() && !ctx.quiet() && !ctx.json()) {
                const v1::AwaitedEstimates& awaited = job.awaiting_estimates();
                std::cout << "awaiting estimates for step " << awaited.step() << " (scan "
                          << (awaited.scan_artifact().empty() ? "empty" : awaited.scan_artifact()) << ")\n";
              }
              return kExitOk;
            });
}

}  // namespace

void AddPickCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("pick", "Picking jobs: a mounted robot empties a bin fill's bin, step by step");
  group->require_subcommand(1);
  AddPickRun(*group, ctx);
  AddJobWatch(*group, ctx, "Follow a picking job until it ends and print its summary; exit 0 if it succeeded",
              PickFinish(ctx), true);
  AddPickResume(*group, ctx);
  AddPickGet(*group, ctx);
  AddPickEstimates(*group, ctx);
  AddJobList(*group, ctx, "picking", "List picking jobs");
  AddJobCancel(*group, ctx, "Cancel a picking job; the scene keeps the pile as the last step left it");
  AddJobDelete(*group, ctx, "Delete an ended picking job and its artifacts (the scene stays as the job left it)");
  AddJobArtifacts(*group, ctx);
}

}  // namespace vscan::cli
