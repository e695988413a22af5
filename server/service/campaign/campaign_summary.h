#pragma once
// campaign.json: what every step of a campaign did (captured, unreachable, colliding), with its
// poses and file name, written when the campaign ends; the job's ReportWriter prints it as
// proto/vscan/v1/reports.proto's CampaignReport.

#include <cstdint>
#include <string>
#include <vector>

#include "service/campaign/campaign_plan.h"
#include "robot_registry/arm_kinematics.h"
#include "service/job/job_events.h"

namespace vscan::service {

struct CampaignStepRecord {
  uint32_t step = 0;
  uint32_t rotation_index = 0;
  uint32_t viewpoint_index = 0;
  double table_angle_deg = 0.0;
  std::string outcome;  // "captured", "unreachable", "collision"
  std::string message;
  double miss_distance = 0.0;
  uint64_t seed = 0;
  bool has_arm = false;
  robot_registry::ArmState arm;
  std::string file;  // scan artifact name when captured
  std::string artifact_id;
  uint64_t points = 0;
  uint64_t rejected_dark = 0;
  uint64_t rejected_saturated = 0;
};

// The step's scan as the job records it with its artifact.
ScanArtifact ScanArtifactOf(const CampaignStepRecord& record);

}  // namespace vscan::service
