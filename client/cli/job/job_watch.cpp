#include "job/job_watch.h"

#include <unistd.h>

#include <iostream>
#include <memory>
#include <optional>

#include "campaign/campaign_report.h"
#include "job/job_download.h"
#include "model/model_report.h"
#include "session/app_main.h"
#include "session/progress.h"

namespace vscan::cli {
namespace {

std::string Counter(const v1::Job& job) {
  return "[" + std::to_string(job.steps_done()) + "/" + std::to_string(job.steps_total()) + "] ";
}

// The command that picks the watch up again.
std::string WatchCommand(const v1::Job& job) { return "vscan " + JobGroup(job.kind()) + " watch " + job.job_id(); }

// One line of --json output per event: the event and where the job stands.
std::string EventJson(const v1::WatchJobResponse& response) {
  const v1::Job& job = response.job();
  return "{\"event\":" + ToJson(response.event()) + ",\"jobId\":" + JsonQuote(job.job_id()) +
         ",\"state\":" + JsonQuote(v1::JobState_Name(job.state())) + ",\"stepsDone\":" +
         std::to_string(job.steps_done()) + ",\"stepsTotal\":" + std::to_string(job.steps_total()) + "}";
}

}  // namespace

int WatchJobToEnd(Context& ctx, const std::string& job_id, WatchResult* result) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const bool chatty = !ctx.json() && !ctx.quiet();
  std::optional<ProgressBar> bar;
  const bool tty = chatty && ::isatty(STDERR_FILENO) != 0;
  bool first = true;
  const Status status = client->WatchJob(job_id, [&](const v1::WatchJobResponse& response) {
    result->job = response.job();
    const v1::JobEvent& event = response.event();
    if (!bar) bar.emplace(response.job().kind().empty() ? "job" : response.job().kind(), "steps", chatty);
    if (event.has_alignment()) result->alignments.push_back(event.alignment());
    // A step that stored nothing says why in its first event (steps_done counts it already).
    if (!first && !event.has_artifact() && !event.has_alignment() && !event.message().empty() &&
        response.job().steps_done() > 0 && !JobFinished(response.job().state())) {
      result->notes.emplace(event.step(), StepNote{event.message(), event.pose_reached()});
    }
    if (ctx.json()) {
      ctx.EmitJson(EventJson(response));
    } else if (chatty && event.has_alignment()) {
      bar->Finish();
      std::cout << Counter(response.job()) << FormatScanAlignment(event.alignment()) << std::endl;
    } else if (chatty && !event.message().empty() && (!tty || !event.has_artifact())) {
      bar->Finish();
      std::cout << Counter(response.job()) << event.message() << std::endl;
    }
    bar->Update(response.job().steps_done(), response.job().steps_total());
    first = false;
    return !JobFinished(response.job().state());
  });
  if (bar) bar->Finish();
  if (!status.ok()) return ctx.ServerError(status);
  // The stream may end before the job does (a server going down); ask where it stands.
  const auto job = client->GetJob(job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  result->job = *job;
  if (!JobFinished(job->state())) {
    return ctx.ServerError(Unavailable("job " + job_id + ": the watch ended while the job is " +
                                       JobStateName(job->state()) + "; run `" + WatchCommand(*job) + "`"));
  }
  return kExitOk;
}

std::string JobGroup(const std::string& kind) {
  static const std::map<std::string, std::string> kGroups = {
      {"campaign", "campaign"}, {"model", "model"}, {"bin_fill", "bin"}, {"dataset", "dataset"}, {"picking", "pick"}};
  const auto group = kGroups.find(kind);
  return group == kGroups.end() ? kind : group->second;
}

bool SayStarted(Context& ctx, const v1::Job& job, const std::string& line, const std::string& json_extra, bool detach) {
  if (!detach) {
    ctx.Say(line);
    return false;
  }
  if (ctx.json()) ctx.EmitJson("{\"job\":" + ToJson(job) + json_extra + "}");
  ctx.Done(line + "; follow it with `" + WatchCommand(job) + "`", job.job_id());
  return true;
}

std::string RunDirectory(const std::string& out_dir, bool no_download, const std::string& name,
                         const std::string& job_id) {
  if (no_download) return "";
  return out_dir.empty() ? name + "-" + job_id : out_dir;
}

int FollowJob(Context& ctx, const std::string& job_id, const std::string& out_dir, JobClock::time_point started,
              const JobFinish& finish) {
  WatchResult watched;
  if (const int rc = WatchJobToEnd(ctx, job_id, &watched); rc != kExitOk) return rc;
  std::vector<std::string> files;
  if (!out_dir.empty()) {
    if (const int rc = DownloadArtifacts(ctx, watched.job, out_dir, &files); rc != kExitOk) return rc;
  }
  return finish(watched, out_dir, files, std::chrono::duration<double>(JobClock::now() - started).count());
}

void AddJobWatch(CLI::App& group, Context& ctx, const std::string& help, JobFinish finish, bool with_output) {
  auto* cmd = group.add_subcommand("watch", help);
  auto id = std::make_shared<std::string>();
  auto out_dir = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  if (with_output) cmd->add_option("-o,--out", *out_dir, "Download the artifacts into this directory");
  OnRun(cmd, ctx, [&ctx, id, out_dir, finish] { return FollowJob(ctx, *id, *out_dir, JobClock::now(), finish); });
}

void AddJobGet(CLI::App& group, Context& ctx, const std::string& help, std::function<int(const v1::Job&)> show) {
  auto* cmd = group.add_subcommand("get", help);
  auto id = std::make_shared<std::string>();
  cmd->add_option("JOB", *id, "Job id")->required();
  OnRun(cmd, ctx, [&ctx, id, show = std::move(show)]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto job = client->GetJob(*id);
    if (!job.ok()) return ctx.ServerError(job.status());
    if (ctx.json()) {
      ctx.EmitJson(ToJson(*job));
      return kExitOk;
    }
    ctx.Print("job " + DescribeJob(*job));
    return show(*job);
  });
}

}  // namespace vscan::cli
