#include "api/reports/report_convert.h"

namespace vscan::api {

v1::PickingReport PickingReportMessage(const service::PickingPlan& plan, const service::PickingJobReport& report) {
  v1::PickingReport out;
  out.set_job_id(report.job_id);
  out.set_name(report.name);
  out.set_state(store::JobStateName(report.state));
  out.set_message(report.message);
  out.set_scene_id(plan.scene_id);
  out.set_bin_job_id(report.bin_job_id);
  out.set_mount_id(plan.mount_id);
  out.set_perception(service::PerceptionName(plan.perception));
  out.set_parts_at_start(static_cast<uint32_t>(report.parts_at_start));
  if (!report.result) return out;
  const picking::EmptyBinResult& result = *report.result;
  out.set_picked(static_cast<uint32_t>(result.picked));
  out.set_fell_out(static_cast<uint32_t>(result.fell_out));
  out.set_left(static_cast<uint32_t>(result.pile.size()));
  out.set_end(result.end);
  for (size_t i = 0; i < result.steps.size(); ++i) {
    const picking::PickStep& step = result.steps[i];
    ++(*out.mutable_outcomes())[picking::StepOutcomeName(step.outcome)];
    v1::PickingReportStep* s = out.add_steps();
    s->set_step(static_cast<uint32_t>(step.step));
    s->set_parts_before(static_cast<uint32_t>(step.parts_before));
    s->set_estimates(static_cast<uint32_t>(step.estimates));
    s->set_pickable_estimates(static_cast<uint32_t>(step.pickable_estimates));
    s->set_outcome(picking::StepOutcomeName(step.outcome));
    s->set_detail(step.detail);
    if (step.picked) {
      s->set_picked_part(plan.bin.parts[step.picked->type].name);
      s->set_picked_instance(static_cast<uint32_t>(step.picked->instance));
    }
    if (step.outcome != picking::StepOutcome::kNothingFound && step.outcome != picking::StepOutcome::kNothingPickable) {
      AddMatrix(step.world_from_tool, s->mutable_world_from_tool());
    }
    s->set_fell_out(static_cast<uint32_t>(step.fell_out));
    s->set_perceive_s(step.perceive_s);
    s->set_plan_s(step.plan_s);
    s->set_settle_s(step.settle_s);
    if (i < report.scan_artifacts.size()) s->set_scan_artifact(report.scan_artifacts[i]);
    if (i < report.truth_artifacts.size()) s->set_truth_artifact(report.truth_artifacts[i]);
  }
  return out;
}

v1::PickingStepTruth PickingStepTruthMessage(const service::PickingPlan& plan, const service::StepView& view) {
  v1::PickingStepTruth out;
  out.set_step(static_cast<uint32_t>(view.step));
  for (const physics::PlacedPart& part : view.truth) {
    v1::PickingPose* pose = out.add_parts();
    pose->set_part(plan.bin.parts[part.type].name);
    pose->set_instance(static_cast<uint32_t>(part.instance));
    AddMatrix(part.world_from_part, pose->mutable_world_from_part());
  }
  for (const picking::Estimate& estimate : view.estimates) {
    v1::PickingPose* pose = out.add_estimates();
    pose->set_part(plan.bin.parts[estimate.type].name);
    pose->set_score(estimate.score);
    AddMatrix(estimate.world_from_part, pose->mutable_world_from_part());
  }
  return out;
}

}  // namespace vscan::api
