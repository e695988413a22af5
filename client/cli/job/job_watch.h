#pragma once
// Follows a running job of any kind: a progress bar on a terminal, one line per event otherwise
// (one JSON line with --json), one line per scan as it is aligned; and the flow every job command
// shares around it: say the job started, follow it, download its files, report.

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "campaign/campaign_report.h"
#include "session/context.h"

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

// The command group of a job kind: `vscan GROUP watch JOB` follows it.
std::string JobGroup(const std::string& kind);

using JobClock = std::chrono::steady_clock;
// What a job command reports once its job has ended, given the job as watched, the directory its
// files went to and their paths (both empty when nothing was downloaded), and the client's seconds.
using JobFinish = std::function<int(const WatchResult& watched, const std::string& out_dir,
                                    const std::vector<std::string>& files, double seconds)>;

// Says the job started (line). With detach that is the command's result, with how to follow it
// (json_extra joins the job in --json output), and true is returned: the command is done.
bool SayStarted(Context& ctx, const v1::Job& job, const std::string& line, const std::string& json_extra, bool detach);
// Where a run downloads its job's files: out_dir, else ./NAME-JOBID; empty with no_download.
std::string RunDirectory(const std::string& out_dir, bool no_download, const std::string& name,
                         const std::string& job_id);
// Follows job_id to its end, downloads its artifacts into out_dir unless it is empty, then finishes.
int FollowJob(Context& ctx, const std::string& job_id, const std::string& out_dir, JobClock::time_point started,
              const JobFinish& finish);
// `GROUP get JOB`: the job printed whole with --json, else its "job ..." line and then what
// show prints of its kind (its exit code is the command's).
void AddJobGet(CLI::App& group, Context& ctx, const std::string& help, std::function<int(const v1::Job&)> show);
// `GROUP watch JOB`, and with with_output `-o DIR` for its artifacts.
void AddJobWatch(CLI::App& group, Context& ctx, const std::string& help, JobFinish finish, bool with_output);

}  // namespace vscan::cli
