#pragma once
// Follows a running job (a campaign or a model job): a progress bar on a terminal, one line per
// event otherwise, and one line per scan as it is aligned.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "campaign_report.h"
#include "context.h"

namespace vscan::cli {

struct WatchResult {
  // The job as it ended.
  v1::Job job;
  // Messages of events about steps that stored no scan, by step.
  std::map<uint32_t, StepNote> notes;
  // The scans' alignments in the order the job reported them.
  std::vector<v1::ScanAlignment> alignments;
};

// Returns an exit code: kExitOk once the job has finished (whatever its state), else the error's.
int WatchJobToEnd(Context& ctx, const std::string& job_id, WatchResult* result);

}  // namespace vscan::cli
