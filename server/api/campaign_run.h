#pragma once
// Runs a validated campaign on a job-runner thread: every viewpoint at every table angle
// (rotation-major), each captured scan stored as a PLY artifact, every step reported as an event,
// and campaign.json written when the campaign ends.

#include <string>

#include "api/campaign_spec.h"
#include "api/job_tracker.h"
#include "api/service_context.h"
#include "jobs/job_runner.h"

namespace vscan::api {

void RunCampaign(ServiceContext& context, JobTracker& tracker, const std::string& job_id, const CampaignPlan& plan,
                 jobs::JobControl& control);

// The state a job ends in when it stops for reason.
store::JobState StoppedState(jobs::StopReason reason);

// "scan-r{rotation:02}-v{viewpoint:02}.ply"
std::string ScanArtifactName(uint32_t rotation, uint32_t viewpoint);

}  // namespace vscan::api
