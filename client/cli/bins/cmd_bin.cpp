// `vscan bin fill|watch|get|list|cancel|delete|artifacts|scan`.

#include <chrono>
#include <cstdio>
#include <optional>

#include "bins/bin_plan.h"
#include "bins/bin_report.h"
#include "bins/bin_scan.h"
#include "bins/bin_setup.h"
#include "campaign/campaign_report.h"
#include "job/job_commands.h"
#include "job/job_download.h"
#include "job/job_watch.h"
#include "model/model_report.h"
#include "session/commands.h"

namespace vscan::cli {
namespace {

struct FillArgs {
  std::string plan;
  std::string out_dir;
  bool no_download = false;
  bool detach = false;
};

// The end of `fill` and `watch`: the summary of bin.json (or JSON), the files, the job's exit code.
int Finish(Context& ctx, const v1::Job& job, const std::string& out_dir, const std::vector<std::string>& files,
           double seconds) {
  std::optional<v1::BinReport> report;
  if (const int rc = FetchBinReport(ctx, job, &report); rc != kExitOk) return rc;
  if (ctx.json()) {
    ctx.EmitJson("{\"job\":" + ToJson(job) + ",\"sceneId\":" + JsonQuote(job.bin_fill().scene_id()) +
                 ",\"outputDir\":" + JsonQuote(out_dir) + ",\"files\":" + JsonStrings(files) +
                 (report ? ",\"bin\":" + ReportJson(*report) : "") + ",\"clientSeconds\":" + std::to_string(seconds) +
                 "}");
    return JobExitCode(job.state());
  }
  if (!ctx.quiet()) {
    std::cout << "job " << job.job_id() << " " << JobStateName(job.state()) << ": " << job.message() << '\n';
    if (report) std::cout << FormatBinReport(*report);
    if (!out_dir.empty()) std::cout << "files in " << out_dir << '\n';
  } else {
    ctx.Print(job.job_id());
  }
  return JobExitCode(job.state());
}

JobFinish BinFinish(Context& ctx) {
  return [&ctx](const WatchResult& watched, const std::string& out_dir, const std::vector<std::string>& files,
                double seconds) { return Finish(ctx, watched.job, out_dir, files, seconds); };
}

int RunFill(Context& ctx, const FillArgs& args) {
  const auto started = std::chrono::steady_clock::now();
  const auto plan = LoadBinPlan(args.plan);
  if (!plan.ok()) {
    if (plan.status().code() == StatusCode::kInvalidArgument) return ctx.UsageError(plan.status().message());
    return ctx.LocalError(plan.status());
  }
  if (const int rc = CheckBinPlanOnServer(ctx, *plan); rc != kExitOk) return rc;
  BinSetup setup;
  if (const int rc = SetUpBin(ctx, *plan, &setup); rc != kExitOk) {
    UndoBinSetup(ctx, setup);
    return rc;
  }
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const auto job = client->StartBinFill(setup.spec);
  if (!job.ok()) {
    const int rc = ReportBinError(ctx, *plan, job.status());
    const StatusCode code = job.status().code();
    if (code != StatusCode::kDeadlineExceeded && code != StatusCode::kCancelled) UndoBinSetup(ctx, setup);
    return rc;
  }
  const std::string started_line = "started bin fill job " + job->job_id() + " (" +
                                   std::to_string(job->steps_total()) + " parts into scene " + setup.scene_id + ")";
  if (SayStarted(ctx, *job, started_line, ",\"sceneId\":" + JsonQuote(setup.scene_id), args.detach)) return kExitOk;
  const std::string out_dir = RunDirectory(args.out_dir, args.no_download, plan->name, job->job_id());
  return FollowJob(ctx, job->job_id(), out_dir, started, BinFinish(ctx));
}

void AddFill(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<FillArgs>();
  auto* cmd = group.add_subcommand("fill", "Fill a bin as a YAML plan describes; the settled parts join the scene");
  cmd->add_option("PLAN", args->plan, "Plan file (YAML; see docs/BINS.md)")->required();
  cmd->add_option("-o,--output", args->out_dir, "Directory for bin.json and job.json (default: ./<name>-<job id>)");
  cmd->add_flag("--no-download", args->no_download, "Leave bin.json on the server");
  cmd->add_flag("--detach", args->detach, "Start the fill, print its job id and return");
  OnRun(cmd, ctx, [&ctx, args] { return RunFill(ctx, *args); });
}

void AddBinGet(CLI::App& group, Context& ctx) {
  const char* help = "Show a bin fill: state, message, the summary of its bin.json";
  AddJobGet(group, ctx, help, [&ctx](const v1::Job& job) -> int {
    std::optional<v1::BinReport> report;
    if (const int rc = FetchBinReport(ctx, job, &report); rc != kExitOk) return rc;
    if (report && !ctx.quiet()) std::cout << FormatBinReport(*report);
    return kExitOk;
  });
}

}  // namespace

void AddBinCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("bin", "Bin picking scenes: fill a bin with parts, scan it with ground truth, localize and score");
  group->require_subcommand(1);
  AddFill(*group, ctx);
  AddJobWatch(*group, ctx, "Follow a bin fill until it ends; exit 0 if it succeeded", BinFinish(ctx), false);
  AddBinGet(*group, ctx);
  AddJobList(*group, ctx, "bin_fill", "List bin fill jobs");
  AddJobCancel(*group, ctx, "Cancel a bin fill; the scene stays as it was");
  AddJobDelete(*group, ctx, "Delete an ended bin fill job and its bin.json (the scene keeps its objects)");
  AddJobArtifacts(*group, ctx);
  AddBinScan(*group, ctx);
  AddLocalizationCommands(*group, ctx);  // also at the top level, for clouds that are not bins
}

}  // namespace vscan::cli
