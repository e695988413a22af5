#pragma once
// Follows a running job: a progress bar on a terminal, one line per event otherwise.

#include <cstdint>
#include <map>
#include <string>

#include "campaign_report.h"
#include "context.h"

namespace vscan::cli {

struct WatchResult {
  // The job as it ended.
  v1::Job job;
  // Messages of events about steps that stored no scan, by step.
  std::map<uint32_t, StepNote> notes;
};

// Returns an exit code: kExitOk once the job has finished (whatever its state), else the error's.
int WatchCampaign(Context& ctx, const std::string& job_id, WatchResult* result);

}  // namespace vscan::cli
