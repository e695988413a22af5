// `vscan campaign run|resume|list|get|watch|cancel|delete|artifacts`.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "campaign/campaign_plan.h"
#include "campaign/campaign_report.h"
#include "campaign/campaign_setup.h"
#include "job/job_commands.h"
#include "job/job_download.h"
#include "job/job_watch.h"
#include "model/model_fetch.h"
#include "model/model_report.h"
#include "session/commands.h"
#include "session/text_format.h"

namespace vscan::cli {
namespace {

struct CampaignRunArgs {
  std::string plan;
  std::string out_dir;
  bool no_download = false;
  bool detach = false;
};

// The end of `run` and `watch`: the table (or JSON), the files, the exit code of the job's state.
int Finish(Context& ctx, const WatchResult& watched, const std::string& out_dir, const std::vector<std::string>& files,
           const std::string& extra_json, double seconds) {
  const v1::Job& job = watched.job;
  const auto rows = CampaignRows(job, watched.notes);
  // A campaign that aligned its scans leaves model.json.
  std::optional<v1::ModelReport> model;
  if (const int rc = FetchModelReport(ctx, job, &model); rc != kExitOk) return rc;
  if (ctx.json()) {
    ctx.EmitJson("{\"job\":" + ToJson(job) + extra_json + ",\"outputDir\":" + JsonQuote(out_dir) +
                 ",\"files\":" + JsonStrings(files) + ",\"steps\":" + CampaignRowsJson(rows) +
                 (model ? ",\"model\":" + ReportJson(*model) : "") +
                 ",\"clientSeconds\":" + std::to_string(seconds) + "}");
    return JobExitCode(job.state());
  }
  if (!ctx.quiet()) {
    std::cout << CampaignTable(rows);
    size_t captured = 0;
    uint64_t points = 0;
    for (const auto& row : rows) {
      captured += row.captured;
      points += row.points;
    }
    std::cout << "job " << job.job_id() << " " << JobStateName(job.state()) << ": " << captured << " of " << rows.size()
              << " scans, " << points << " points in " << Format("%.1f s", seconds)
              << (job.message().empty() ? "" : "; " + job.message()) << '\n';
    if (model) std::cout << FormatModelReport(*model);
    if (!out_dir.empty()) std::cout << "files in " << out_dir << '\n';
  } else {
    ctx.Print(job.job_id());
  }
  return JobExitCode(job.state());
}

// extra_json joins the job in --json output (the scene and mount a run set up).
JobFinish CampaignFinish(Context& ctx, const std::string& extra_json = "") {
  return [&ctx, extra_json](const WatchResult& watched, const std::string& out_dir,
                            const std::vector<std::string>& files, double seconds) {
    return Finish(ctx, watched, out_dir, files, extra_json, seconds);
  };
}

int RunCampaign(Context& ctx, const CampaignRunArgs& args) {
  const auto started = std::chrono::steady_clock::now();
  const auto plan = LoadCampaignPlan(args.plan);
  if (!plan.ok()) {
    if (plan.status().code() == StatusCode::kInvalidArgument) return ctx.UsageError(plan.status().message());
    return ctx.LocalError(plan.status());
  }
  // Nothing is uploaded for a plan the server would refuse; what a failed setup created is removed.
  if (const int rc = CheckPlanOnServer(ctx, *plan); rc != kExitOk) return rc;
  CampaignSetup setup;
  if (const int rc = SetUpCampaign(ctx, *plan, &setup); rc != kExitOk) {
    UndoCampaignSetup(ctx, setup);
    return rc;
  }
  v1::CampaignSpec spec = plan->spec;
  spec.set_scene_id(setup.scene_id);
  spec.set_mount_id(setup.mount_id);

  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->StartCampaign(spec);
  if (!job.ok()) {
    const int rc = ReportCallError(ctx, *plan, PlanCall::kStartCampaign, job.status());
    // After a lost answer the job may exist and need what setup made.
    const StatusCode code = job.status().code();
    if (code != StatusCode::kDeadlineExceeded && code != StatusCode::kCancelled) UndoCampaignSetup(ctx, setup);
    return rc;
  }
  const std::string ids = ",\"sceneId\":" + JsonQuote(setup.scene_id) + ",\"mountId\":" + JsonQuote(setup.mount_id);
  const std::string line =
      "started campaign job " + job->job_id() + " (" + std::to_string(job->steps_total()) + " steps)";
  if (SayStarted(ctx, *job, line, ids, args.detach)) return kExitOk;
  const std::string out_dir = RunDirectory(args.out_dir, args.no_download, plan->name, job->job_id());
  return FollowJob(ctx, job->job_id(), out_dir, started, CampaignFinish(ctx, ids));
}

void AddCampaignRun(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<CampaignRunArgs>();
  auto* cmd = group.add_subcommand("run", "Set up what a YAML plan describes, run its campaign, download the scans");
  cmd->add_option("PLAN", args->plan, "Plan file (YAML; see docs/CAMPAIGNS.md)")->required();
  cmd->add_option("-o,--output", args->out_dir, "Directory for the scans (default: ./<plan name>-<job id>)");
  cmd->add_flag("--no-download", args->no_download, "Leave the scans on the server");
  cmd->add_flag("--detach", args->detach, "Start the campaign, print its job id and return");
  OnRun(cmd, ctx, [&ctx, args] { return RunCampaign(ctx, *args); });
}

struct ResumeArgs {
  std::string job_id;
  std::string out_dir;
  bool watch = false;
  bool no_download = false;
};

int ResumeCampaign(Context& ctx, const ResumeArgs& args) {
  const auto started = std::chrono::steady_clock::now();
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->ResumeJob(args.job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  const size_t stored = static_cast<size_t>(std::count_if(job->artifacts().begin(), job->artifacts().end(),
                                                          [](const v1::Artifact& a) { return a.has_scan(); }));
  const std::string what = "resumed campaign job " + job->job_id() + " (" + std::to_string(stored) + " scans stored, " +
                           std::to_string(job->steps_total()) + " steps)";
  if (SayStarted(ctx, *job, what, "", !args.watch)) return kExitOk;
  const std::string& named = job->campaign().name();
  const std::string name = named.empty() ? "campaign" : named;
  const std::string out_dir = RunDirectory(args.out_dir, args.no_download, name, job->job_id());
  return FollowJob(ctx, job->job_id(), out_dir, started, CampaignFinish(ctx));
}

void AddResume(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<ResumeArgs>();
  auto* cmd = group.add_subcommand(
      "resume", "Run an interrupted, cancelled or failed campaign again as the same job: only its missing steps");
  cmd->add_option("JOB", args->job_id, "Job id")->required();
  cmd->add_flag("--watch", args->watch, "Follow the job until it ends and download its files");
  cmd->add_option("-o,--output", args->out_dir, "With --watch: directory for the files (default: ./<name>-<job id>)");
  cmd->add_flag("--no-download", args->no_download, "With --watch: leave the files on the server");
  OnRun(cmd, ctx, [&ctx, args] { return ResumeCampaign(ctx, *args); });
}

void AddCampaignGet(CLI::App& group, Context& ctx) {
  AddJobGet(group, ctx, "Show a campaign job: state, steps, artifacts", [&ctx](const v1::Job& job) -> int {
    const v1::CampaignSpec& spec = job.campaign();
    ctx.Print("scene " + spec.scene_id() + "  mount " + spec.mount_id() + "  " +
              std::to_string(spec.viewpoints_size()) + " viewpoints x " +
              std::to_string(std::max<uint32_t>(spec.rotations(), 1)) + " table angles");
    if (!ctx.quiet()) std::cout << CampaignTable(CampaignRows(job, {}));
    return kExitOk;
  });
}

}  // namespace

void AddCampaignCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("campaign", "Scan campaigns from YAML plans: run, follow, fetch the scans");
  group->require_subcommand(1);
  AddCampaignRun(*group, ctx);
  AddResume(*group, ctx);
  AddJobList(*group, ctx, "campaign", "List campaign jobs");
  AddCampaignGet(*group, ctx);
  AddJobWatch(*group, ctx, "Follow a campaign job until it ends; exit 0 if it succeeded", CampaignFinish(ctx), false);
  AddJobCancel(*group, ctx, "Cancel a campaign job; scans stored so far are kept");
  AddJobDelete(*group, ctx, "Delete an ended campaign job and its scans from the server");
  AddJobArtifacts(*group, ctx);
}

}  // namespace vscan::cli
