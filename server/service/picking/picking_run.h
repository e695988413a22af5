#pragma once
// Runs a picking job on a job-runner thread: an event per step, each step's scan (PLY) and truth
// (step-NNN-truth.json) as artifacts, picking.json however it ends. The scene changes as parts
// are picked; a stopped job leaves it as its last finished step left it, and a job run again on
// the scene picks on from there.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "jobs/job_runner.h"
#include "service/job/job_events.h"
#include "service/picking/estimates_inbox.h"
#include "service/picking/picking_session.h"

namespace vscan::service {

// Perception::kClient: where a step waits for the client's estimates, and the job's durable
// record of them (the caller keeps it in the job's directory).
struct ClientEstimates {
  EstimatesInbox* inbox = nullptr;
  // The first step a run takes: the steps before it finished in an earlier run of the job.
  std::function<size_t()> first_step;
  // The estimates stored for a step, when they were sent for the pile it sees; nullopt otherwise.
  std::function<std::optional<std::vector<picking::Estimate>>(const AwaitedStep&)> stored;
  // After the step's pile was written to the scene.
  std::function<void(size_t step)> step_done;
};

// client is required with Perception::kClient and unused otherwise.
void RunPicking(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const std::string& name,
                const std::string& bin_job_id, const PickingPlan& plan, jobs::JobControl& control,
                const ClientEstimates* client = nullptr);

}  // namespace vscan::service
