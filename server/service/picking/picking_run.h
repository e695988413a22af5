#pragma once
// Runs a picking job on a job-runner thread: an event per step, each step's scan (PLY) and truth
// (step-NNN-truth.json) as artifacts, picking.json however it ends. The scene changes as parts
// are picked; a stopped job leaves it as its last finished step left it, and a job run again on
// the scene picks on from there.

#include <string>

#include "jobs/job_runner.h"
#include "service/job/job_events.h"
#include "service/picking/picking_session.h"

namespace vscan::service {

void RunPicking(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const std::string& name,
                const std::string& bin_job_id, const PickingPlan& plan, jobs::JobControl& control);

}  // namespace vscan::service
