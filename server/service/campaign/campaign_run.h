#pragma once
// Runs a validated campaign on a job-runner thread: every viewpoint at every table angle
// (rotation-major), each captured scan stored as a PLY artifact, every step reported as an event,
// and campaign.json written when the campaign ends.

#include <cstdint>
#include <map>
#include <string>

#include "jobs/job_runner.h"
#include "service/campaign/campaign_plan.h"
#include "service/campaign/campaign_summary.h"
#include "service/job/job_events.h"
#include "service/context/service_context.h"

namespace vscan::service {

// A scan an earlier run of the same job stored: a resumed run passes over its step.
struct StoredCampaignScan {
  CampaignStepRecord record;  // step, indices, table angle, arm, file, artifact id, points
  std::string sha256;         // its PLY's blob, read back when the campaign models its scans
};

// The stored scans of a resumed job by step; empty for a first run.
using StoredCampaignScans = std::map<uint32_t, StoredCampaignScan>;

// Events and artifacts go to recorder; job_id names the job in logs and scratch files. Steps in
// stored are not captured again; every other step is, with the seed an uninterrupted run gives it.
void RunCampaign(ServiceContext& context, JobRecorder& recorder, const std::string& job_id, const CampaignPlan& plan,
                 jobs::JobControl& control, const StoredCampaignScans& stored = {});

// "scan-r{rotation:02}-v{viewpoint:02}.ply"
std::string ScanArtifactName(uint32_t rotation, uint32_t viewpoint);

}  // namespace vscan::service
