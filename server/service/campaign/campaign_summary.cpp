#include "service/campaign/campaign_summary.h"

namespace vscan::service {

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
