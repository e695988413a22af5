#pragma once
// `vscan pick estimates JOB --step N FILE`: a localizer's estimates for the step a picking job
// with client perception awaits (JobService.SubmitPickingEstimates).

#include <CLI/CLI.hpp>

#include "session/context.h"

namespace vscan::cli {

void AddPickEstimates(CLI::App& group, Context& ctx);

}  // namespace vscan::cli
