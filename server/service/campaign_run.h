#pragma once
// Runs a validated campaign on a job-runner thread: every viewpoint at every table angle
// (rotation-major), each captured scan stored as a PLY artifact, every step reported as an event,
// and campaign.json written when the campaign ends.

#include <string>

#include "jobs/job_runner.h"
#include "service/campaign_plan.h"
#include "service/job_events.h"
#include "service/service_context.h"

namespace vscan::service {

// Events and artifacts go to recorder; job_id names the job in logs and scratch files.
void RunCampaign(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const CampaignPlan& plan,
                 jobs::JobControl& control);

// The state a job ends in when it stops for reason.
store::JobState StoppedState(jobs::StopReason reason);

// "scan-r{rotation:02}-v{viewpoint:02}.ply"
std::string ScanArtifactName(uint32_t rotation, uint32_t viewpoint);

}  // namespace vscan::service
