#pragma once
// Runs a planned bin fill on a job-runner thread: an event per simulated second (parts dropped,
// resting, out of the bin), the settled parts and the bin into the scene in one revision when the
// fill ends by itself, and bin.json however it ends (with bin_replay.bin, the parts' poses through
// the fill, whenever the physics ran). A cancelled, stopped or failed fill leaves
// the scene as it was. With a pick check in the plan, the placed parts are then checked
// (cancelled with the job); a check that does not finish ends the job failed or stopped with the
// parts already in the scene.

#include <string>

#include "jobs/job_runner.h"
#include "service/bins/bin_fill_plan.h"
#include "service/job/job_events.h"

namespace vscan::service {

void RunBinFill(scenes::SceneRegistry& registry, JobRecorder& recorder, const std::string& job_id, const BinFillPlan& plan,
                jobs::JobControl& control);

}  // namespace vscan::service
