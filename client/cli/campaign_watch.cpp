#include "campaign_watch.h"

#include <unistd.h>

#include <iostream>

#include "campaign_report.h"
#include "progress.h"

namespace vscan::cli {
namespace {

std::string Counter(const v1::Job& job) {
  return "[" + std::to_string(job.steps_done()) + "/" + std::to_string(job.steps_total()) + "] ";
}

}  // namespace

int WatchCampaign(Context& ctx, const std::string& job_id, WatchResult* result) {
  auto* client = ctx.GetClient();
  if (!client) return ctx.last_exit();
  const bool chatty = !ctx.json() && !ctx.quiet();
  ProgressBar bar("campaign", "steps", chatty);
  const bool tty = chatty && ::isatty(STDERR_FILENO) != 0;
  bool first = true;
  const Status status = client->WatchJob(job_id, [&](const v1::WatchJobResponse& response) {
    result->job = response.job();
    const v1::JobEvent& event = response.event();
    // A step that stored nothing says why in its event (steps_done counts it already).
    if (!first && !event.has_artifact() && !event.message().empty() && response.job().steps_done() > 0 &&
        !JobFinished(response.job().state())) {
      result->notes[event.step()] = {event.message(), event.pose_reached()};
    }
    if (chatty && !event.message().empty() && (!tty || !event.has_artifact())) {
      bar.Finish();
      std::cout << Counter(response.job()) << event.message() << std::endl;
    }
    bar.Update(response.job().steps_done(), response.job().steps_total());
    first = false;
    return !JobFinished(response.job().state());
  });
  bar.Finish();
  if (!status.ok()) return ctx.ServerError(status);
  // The stream may end before the job does (a server going down); ask where it stands.
  const auto job = client->GetJob(job_id);
  if (!job.ok()) return ctx.ServerError(job.status());
  result->job = *job;
  if (!JobFinished(job->state())) {
    return ctx.ServerError(Unavailable("job " + job_id + ": the watch ended while the job is " +
                                       JobStateName(job->state()) + "; run `vscan campaign watch " + job_id + "`"));
  }
  return kExitOk;
}

}  // namespace vscan::cli
