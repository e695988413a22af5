#include "service/campaign/campaign_summary.h"

#include "service/job/json_writer.h"

namespace vscan::service {

std::string CampaignSummaryJson(const std::string& job_id, const std::string& final_state, const CampaignPlan& plan,
                                const std::vector<CampaignStepRecord>& steps) {
  JsonWriter json;
  json.Open('{');
  json.Key("job_id").Value(job_id);
  json.Key("state").Value(final_state);
  json.Key("name").Value(plan.name);
  json.Key("scene_id").Value(plan.scene_id);
  json.Key("mount_id").Value(plan.mount_id);
  json.Key("seed").Value(plan.seed);
  json.Key("rotations").Value(uint64_t{plan.rotations});
  json.Key("rotation_step_deg").Value(plan.rotation_step_deg);
  json.Key("start_angle_deg").Value(plan.start_angle_deg);
  json.Key("steps_total").Value(uint64_t{plan.scans_total()});
  json.Key("viewpoints").Open('[');
  for (const CampaignViewpoint& v : plan.viewpoints) {
    json.Open('{');
    json.Key("position").Vector(v.position);
    json.Key("target").Vector(v.target);
    json.Close('}');
  }
  json.Close(']');
  uint64_t captured = 0;
  for (const CampaignStepRecord& s : steps) captured += s.outcome == "captured";
  json.Key("steps_done").Value(uint64_t{steps.size()});
  json.Key("scans_captured").Value(captured);
  json.Key("steps").Open('[');
  for (const CampaignStepRecord& s : steps) {
    json.Open('{');
    json.Key("step").Value(uint64_t{s.step});
    json.Key("rotation_index").Value(uint64_t{s.rotation_index});
    json.Key("viewpoint_index").Value(uint64_t{s.viewpoint_index});
    json.Key("table_angle_deg").Value(s.table_angle_deg);
    json.Key("outcome").Value(s.outcome);
    json.Key("reached").Value(s.outcome != "unreachable");
    json.Key("message").Value(s.message);
    json.Key("seed").Value(s.seed);
    if (s.outcome == "unreachable") json.Key("miss_distance_m").Value(s.miss_distance);
    if (s.has_arm) {
      json.Key("commanded_joint_positions").Array(s.arm.commanded);
      json.Key("achieved_joint_positions").Array(s.arm.achieved);
      json.Key("commanded_sensor_pose").Matrix(s.arm.commanded_pose);
      json.Key("sensor_pose").Matrix(s.arm.achieved_pose);
    }
    if (!s.file.empty()) {
      json.Key("file").Value(s.file);
      json.Key("artifact_id").Value(s.artifact_id);
      json.Key("points").Value(s.points);
    }
    json.Close('}');
  }
  json.Close(']');
  json.Close('}');
  return json.str() + "\n";
}

ScanArtifact ScanArtifactOf(const CampaignStepRecord& record) {
  ScanArtifact scan;
  scan.rotation_index = record.rotation_index;
  scan.viewpoint_index = record.viewpoint_index;
  scan.table_angle_deg = record.table_angle_deg;
  scan.commanded_sensor_pose = record.arm.commanded_pose;
  scan.sensor_pose = record.arm.achieved_pose;
  scan.commanded_joint_positions = record.arm.commanded;
  scan.achieved_joint_positions = record.arm.achieved;
  scan.points = record.points;
  return scan;
}

}  // namespace vscan::service
