#include "api/reports/report_convert.h"

namespace vscan::api {
namespace {

void Step(const service::CampaignStepRecord& s, v1::CampaignReportStep* out) {
  out->set_step(s.step);
  out->set_rotation_index(s.rotation_index);
  out->set_viewpoint_index(s.viewpoint_index);
  out->set_table_angle_deg(s.table_angle_deg);
  out->set_outcome(s.outcome);
  out->set_reached(s.outcome != "unreachable");
  out->set_message(s.message);
  out->set_seed(static_cast<double>(s.seed));
  if (s.outcome == "unreachable") out->set_miss_distance_m(s.miss_distance);
  if (s.has_arm) {
    SetList(s.arm.commanded, out->mutable_commanded_joint_positions());
    SetList(s.arm.achieved, out->mutable_achieved_joint_positions());
    SetList(s.arm.commanded_pose, out->mutable_commanded_sensor_pose());
    SetList(s.arm.achieved_pose, out->mutable_sensor_pose());
  }
  if (!s.file.empty()) {
    out->set_file(s.file);
    out->set_artifact_id(s.artifact_id);
    out->set_points(static_cast<uint32_t>(s.points));
    if (s.rejected_dark > 0) out->set_rejected_dark(static_cast<uint32_t>(s.rejected_dark));
    if (s.rejected_saturated > 0) out->set_rejected_saturated(static_cast<uint32_t>(s.rejected_saturated));
  }
}

}  // namespace

v1::CampaignReport CampaignReportMessage(const std::string& job_id, const std::string& final_state,
                                         const service::CampaignPlan& plan,
                                         const std::vector<service::CampaignStepRecord>& steps) {
  v1::CampaignReport out;
  out.set_job_id(job_id);
  out.set_state(final_state);
  out.set_name(plan.name);
  out.set_scene_id(plan.scene_id);
  out.set_mount_id(plan.mount_id);
  out.set_seed(static_cast<double>(plan.seed));
  out.set_rotations(plan.rotations);
  out.set_rotation_step_deg(plan.rotation_step_deg);
  out.set_start_angle_deg(plan.start_angle_deg);
  out.set_steps_total(plan.scans_total());
  for (const service::CampaignViewpoint& v : plan.viewpoints) {
    v1::CampaignReportViewpoint* viewpoint = out.add_viewpoints();
    AddVector(v.position, viewpoint->mutable_position());
    AddVector(v.target, viewpoint->mutable_target());
  }
  uint32_t captured = 0;
  for (const service::CampaignStepRecord& s : steps) captured += s.outcome == "captured";
  out.set_steps_done(static_cast<uint32_t>(steps.size()));
  out.set_scans_captured(captured);
  for (const service::CampaignStepRecord& s : steps) Step(s, out.add_steps());
  return out;
}

}  // namespace vscan::api
