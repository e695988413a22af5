#pragma once
// Runs a planned model job on a job-runner thread: alignment (an event per scan), the union as
// aligned.ply, reconstruction (mesh.ply), evaluation against the ground truth (uncovered.ply,
// coverage.png, next best views), and model.json when the job ends, however it ends.

#include <cstdint>
#include <string>

#include "jobs/job_runner.h"
#include "service/job_events.h"
#include "service/model_plan.h"
#include "service/service_context.h"

namespace vscan::service {

// Events and artifacts go to recorder; job_id names the job in logs and in model.json.
void RunModel(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const ModelPlan& plan,
              jobs::JobControl& control);

// The work items a model job reports progress in: one per cloud, the union, and one per later stage.
uint32_t ModelStepsTotal(const ModelPlan& plan);

}  // namespace vscan::service
