#include "job/job_commands.h"

#include <algorithm>
#include <memory>

#include "campaign/campaign_report.h"
#include "job/job_download.h"

namespace vscan::cli {

std::string JsonStrings(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + JsonQuote(items[i]);
  return out + "]";
}

void AddJobList(CLI::App& group, Context& ctx, const std::string& kind, const std::string& help) {
  auto* cmd = group.add_subcommand("list", help);
  OnRun(cmd, ctx, [&ctx, kind]() -> int {
    auto* client = ctx.GetClient();
    if (!client) return ctx.last_exit();
    const auto jobs = client->ListJobs();
    if (!jobs.ok()) return ctx.ServerError(jobs.status());
    std::vector<v1::Job> newest_first;
    for (const auto& job : *jobs) {
      if (job.kind() == kind) newest_first.push_back(job);
    }
    std::stable_sort(newest_first.begin(), newest_first.end(), [](const v1::Job& a, const v1::Job& b) {
      const auto& ta = a.create_time();
      const auto& tb = b.create_time();
      return ta.seconds() != tb.seconds() ? ta.seconds() > tb.seconds() : ta.nanos() > tb.nanos();
    });
    v1::ListJobsResponse listed;
    for (auto& job : newest_first) *listed.add_jobs() = std::move(job);
    if (ctx.json()) {
      ctx.EmitJson(ToJson(listed));
      return kExitOk;
    }
    for (const auto& job : listed.jobs()) ctx.Print(ctx.quiet() ? job.job_id() : DescribeJob(job));
    return kExitOk;
  });
}

void AddJobCancel(CLI::App& group, Context& ctx, const std::string& help) {
  auto* cmd = group.add_subcommand("cancel", help);
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

void AddJobDelete(CLI::App& group, Context& ctx, const std::string& help) {
  auto* cmd = group.add_subcommand("delete", help);
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

void AddJobArtifacts(CLI::App& group, Context& ctx) {
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

}  // namespace vscan::cli
