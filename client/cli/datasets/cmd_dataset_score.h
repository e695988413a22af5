#pragma once
// `vscan dataset score JOB --results results.csv`: a BOP results file scored against a finished
// dataset job's ground truth (JobService.ScoreDatasetResults).

#include "session/app_main.h"

namespace vscan::cli {

void AddDatasetScore(CLI::App& group, Context& ctx);

}  // namespace vscan::cli
