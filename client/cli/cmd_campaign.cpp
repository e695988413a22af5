// `vscan campaign run|list|get|watch|cancel|delete|artifacts`.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "campaign_download.h"
#include "campaign_plan.h"
#include "campaign_report.h"
#include "campaign_setup.h"
#include "campaign_watch.h"
#include "commands.h"

namespace vscan::cli {
namespace {

struct RunArgs {
  std::string plan;
  std::string out_dir;
  bool no_download = false;
  bool detach = false;
};

std::string JsonStrings(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + JsonQuote(items[i]);
  return out + "]";
}

std::string FormatSeconds(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f s", seconds);
  return buf;
}

// The end of `run` and `watch`: the table (or JSON), the files, the exit code of the job's state.
int Finish(Context& ctx, const WatchResult& watched, const std::string& out_dir, const std::vector<std::string>& files,
           const std::string& extra_json, double seconds) {
  const v1::Job& job = watched.job;
  const auto rows = CampaignRows(job, watched.notes);
  if (ctx.json()) {
    ctx.EmitJson("{\"job\":" + ToJson(job) + extra_json + ",\"outputDir\":" + JsonQuote(out_dir) +
                 ",\"files\":" + JsonStrings(files) + ",\"steps\":" + CampaignRowsJson(rows) +
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
              << " scans, " << points << " points in " << FormatSeconds(seconds)
              << (job.message().empty() ? "" : "; " + job.message()) << '\n';
    if (!out_dir.empty()) std::cout << "files in " << out_dir << '\n';
  } else {
    ctx.Print(job.job_id());
  }
  return JobExitCode(job.state());
}

int RunCampaign(Context& ctx, const RunArgs& args) {
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
  if (args.detach) {
    if (ctx.json()) ctx.EmitJson("{\"job\":" + ToJson(*job) + ids + "}");
    ctx.Done("started campaign job " + job->job_id() + " (" + std::to_string(job->steps_total()) + " steps)",
             job->job_id());
    return kExitOk;
  }
  ctx.Say("started campaign job " + job->job_id() + " (" + std::to_string(job->steps_total()) + " steps)");

  WatchResult watched;
  if (const int rc = WatchCampaign(ctx, job->job_id(), &watched); rc != kExitOk) return rc;
  std::string out_dir;
  std::vector<std::string> files;
  if (!args.no_download) {
    out_dir = args.out_dir.empty() ? plan->name + "-" + job->job_id() : args.out_dir;
    if (const int rc = DownloadArtifacts(ctx, watched.job, out_dir, &files); rc != kExitOk) return rc;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return Finish(ctx, watched, out_dir, files, ids, seconds);
}

void AddRun(CLI::App& group, Context& ctx) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = group.add_subcommand("run", "Set up what a YAML plan describes, run its campaign, download the scans");
  cmd->add_option("PLAN", args->plan, "Plan file (YAML; see docs/CAMPAIGNS.md)")->required();
  cmd->add_option("-o,--output", args->out_dir, "Directory for the scans (default: ./<plan name>-<job id>)");
  cmd->add_flag("--no-download", args->no_download, "Leave the scans on the server");
  cmd->add_flag("--detach", args->detach, "Start the campaign, print its job id and return");
  OnRun(cmd, ctx, [&ctx, args] { return RunCampaign(ctx, *args); });
}

void AddList(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("list", "List campaign jobs");
  OnRun(cmd, ctx, [&ctx]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto jobs = client->ListJobs();
    if (!jobs.ok()) return ctx.ServerError(jobs.status());
    std::vector<v1::Job> newest_first;
    for (const auto& job : *jobs) {
      if (job.kind() == "campaign") newest_first.push_back(job);
    }
    std::stable_sort(newest_first.begin(), newest_first.end(), [](const v1::Job& a, const v1::Job& b) {
      const auto& ta = a.create_time();
      const auto& tb = b.create_time();
      return ta.seconds() != tb.seconds() ? ta.seconds() > tb.seconds() : ta.nanos() > tb.nanos();
    });
    v1::ListJobsResponse campaigns;
    for (auto& job : newest_first) *campaigns.add_jobs() = std::move(job);
    if (ctx.json()) {
      ctx.EmitJson(ToJson(campaigns));
      return kExitOk;
    }
    for (const auto& job : campaigns.jobs()) ctx.Print(ctx.quiet() ? job.job_id() : DescribeJob(job));
    return kExitOk;
  });
}

void AddGet(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("get", "Show a campaign job: state, steps, artifacts");
  auto id = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto job = client->GetJob(*id);
    if (!job.ok()) return ctx.ServerError(job.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*job));
      return kExitOk;
    }
    ctx.Print("job " + DescribeJob(*job));
    const v1::CampaignSpec& spec = job->campaign();
    ctx.Print("scene " + spec.scene_id() + "  mount " + spec.mount_id() + "  " +
              std::to_string(spec.viewpoints_size()) + " viewpoints x " +
              std::to_string(std::max<uint32_t>(spec.rotations(), 1)) + " table angles");
    if (!ctx.quiet()) std::cout << CampaignTable(CampaignRows(*job, {}));
    return kExitOk;
  });
}

void AddWatch(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("watch", "Follow a campaign job until it ends; exit 0 if it succeeded");
  auto id = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    const auto started = std::chrono::steady_clock::now();
    WatchResult watched;
    if (const int rc = WatchCampaign(ctx, *id, &watched); rc != kExitOk) return rc;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    return Finish(ctx, watched, "", {}, "", seconds);
  });
}

void AddCancel(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("cancel", "Cancel a campaign job; scans stored so far are kept");
  auto id = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto job = client->CancelJob(*id);
    if (!job.ok()) return ctx.ServerError(job.status());
    if (ctx.json()) ctx.EmitJson(ToJson(*job));
    // A running job stops between two steps, shortly after the request.
    ctx.Done((JobFinished(job->state()) ? "job " : "cancelling job ") + DescribeJob(*job), "");
    return kExitOk;
  });
}

void AddDelete(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("delete", "Delete an ended campaign job and its scans from the server");
  auto id = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id (cancel a running job first)")->required();
  OnRun(cmd, ctx, [&ctx, id]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto deleted = client->DeleteJob(*id);
    if (!deleted.ok()) return ctx.ServerError(deleted.status());
    if (ctx.json()) {
      ctx.EmitJson("{\"jobId\":" + JsonQuote(*id) + ",\"removedFiles\":" + std::to_string(deleted->removed_files()) +
                   ",\"removedBytes\":" + std::to_string(deleted->removed_bytes()) + "}");
    }
    ctx.Done("deleted job " + *id + " (" + std::to_string(deleted->removed_files()) + " files, " +
                 std::to_string(deleted->removed_bytes()) + " bytes freed)",
             *id);
    return kExitOk;
  });
}

void AddArtifacts(CLI::App& group, Context& ctx) {
  auto* cmd = group.add_subcommand("artifacts", "List a job's artifacts, or download them with -o");
  auto id = std::make_shared<std::string>();
  auto dir = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  cmd->add_option("-o,--output", *dir, "Download every artifact into this directory");
  OnRun(cmd, ctx, [&ctx, id, dir]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto job = client->GetJob(*id);
    if (!job.ok()) return ctx.ServerError(job.status());
    std::vector<std::string> files;
    if (!dir->empty()) {
      if (const int rc = DownloadArtifacts(ctx, *job, *dir, &files); rc != kExitOk) return rc;
    }
    if (ctx.json()) {
      std::string artifacts = "[";
      for (int i = 0; i < job->artifacts_size(); ++i) artifacts += (i ? "," : "") + ToJson(job->artifacts(i));
      ctx.EmitJson("{\"jobId\":" + JsonQuote(job->job_id()) + ",\"artifacts\":" + artifacts +
                   "],\"files\":" + JsonStrings(files) + "}");
      return kExitOk;
    }
    for (const auto& artifact : job->artifacts()) {
      ctx.Print(ctx.quiet() ? artifact.artifact_id()
                            : artifact.artifact_id() + "  " + artifact.name() + "  " + artifact.media_type() + "  " +
                                  std::to_string(artifact.size_bytes()) + " bytes");
    }
    if (!dir->empty()) ctx.Say("saved " + std::to_string(files.size()) + " files in " + *dir);
    return kExitOk;
  });
}

}  // namespace

void AddCampaignCommands(CLI::App& app, Context& ctx) {
  auto* group = app.add_subcommand("campaign", "Scan campaigns from YAML plans: run, follow, fetch the scans");
  group->require_subcommand(1);
  AddRun(*group, ctx);
  AddList(*group, ctx);
  AddGet(*group, ctx);
  AddWatch(*group, ctx);
  AddCancel(*group, ctx);
  AddDelete(*group, ctx);
  AddArtifacts(*group, ctx);
}

}  // namespace vscan::cli
