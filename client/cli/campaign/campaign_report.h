#pragma once
// What a campaign produced, step by step, as a text table or JSON.

#include <map>
#include <string>
#include <vector>

#include "vscan/v1/job.pb.h"

namespace vscan::cli {

// What the server said about a step that stored no scan.
struct StepNote {
  std::string message;
  bool pose_reached = false;
};

// One campaign step (viewpoint x table angle) and what became of it.
struct CampaignStepRow {
  uint32_t step = 0;
  uint32_t viewpoint = 0;
  uint32_t rotation = 0;
  double table_angle_deg = 0;
  // The arm reached the viewpoint (a step may still be skipped, e.g. for a collision).
  bool pose_reached = false;
  // A scan was stored for this step.
  bool captured = false;
  uint64_t points = 0;
  std::string file;
  // Between the commanded and the reached (true) sensor pose.
  double position_error_m = 0;
  double orientation_error_deg = 0;
  // Why nothing was captured, when the server said.
  std::string note;
};

// Rows for every step of the job's campaign, rotation-major; notes by step.
std::vector<CampaignStepRow> CampaignRows(const v1::Job& job, const std::map<uint32_t, StepNote>& notes);
std::string CampaignTable(const std::vector<CampaignStepRow>& rows);
// A JSON array of objects with camelCase keys.
std::string CampaignRowsJson(const std::vector<CampaignStepRow>& rows);

// "SUCCEEDED", "RUNNING", ...
std::string JobStateName(v1::JobState state);
bool JobFinished(v1::JobState state);
// 0 for SUCCEEDED, 3 for any other end.
int JobExitCode(v1::JobState state);
// One line: id, state, steps, name, message.
std::string DescribeJob(const v1::Job& job);
// "2026-11-21 23:30:05Z"; empty for an unset time.
std::string FormatTime(const google::protobuf::Timestamp& time);

}  // namespace vscan::cli
