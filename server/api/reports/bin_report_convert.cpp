#include "api/reports/report_convert.h"

#include <map>

#include "grasping/pick_checks.h"
#include "physics/bin_fill.h"

namespace vscan::api {
namespace {

void Types(const service::BinFillPlan& plan, v1::BinReport* out) {
  for (size_t i = 0; i < plan.parts.size(); ++i) {
    const service::BinPartRequest& asked = plan.request.parts[i];
    v1::BinReportType* type = out->add_types();
    type->set_type(static_cast<uint32_t>(i));
    type->set_name(plan.parts[i].name);
    type->set_mesh_id(asked.mesh_id);
    type->set_count(static_cast<uint32_t>(asked.count));
    type->set_source_unit(service::UnitName(plan.meshes[i].source_unit));
    type->set_scale(asked.scale);
    type->set_mass_kg(plan.geometry[i].mass_kg);
    type->set_collision(plan.parts[i].collision == physics::PartCollision::kConvexDecomposition ? "convex_decomposition"
                                                                                                : "convex_hull");
  }
}

void Bin(const service::BinFillPlan& plan, const service::BinFillReport& report, v1::BinReportBin* out) {
  const physics::BinSpec& bin = plan.request.bin;
  if (plan.request.mesh_bin) {
    const physics::BinInterior interior = physics::InteriorOf(bin);
    out->set_mesh_id(plan.request.bin_mesh_id);
    out->set_scale(plan.request.bin_mesh_scale);
    SetList(Eigen::VectorXd(interior.lo), out->mutable_bounds_min());
    SetList(Eigen::VectorXd(interior.hi), out->mutable_bounds_max());
  } else {
    SetList(Eigen::VectorXd(bin.inner_size), out->mutable_inner_size());
    out->set_wall_thickness(bin.wall_thickness);
  }
  AddMatrix(bin.world_from_bin, out->mutable_world_from_bin());
  if (!report.placement) return;
  out->set_object_id(report.placement->bin.object_id);
  out->set_instance_id(report.placement->bin.instance_id);
  if (!plan.request.mesh_bin) out->set_mesh_id(report.placement->bin.mesh_id);
  out->set_label(report.placement->bin.label);
}

// One part's verdict; the grasp in the part frame from the part's settled pose and the tool's.
void Pick(const service::BinPartPick& pick, const Pose3& world_from_part, v1::BinReportPick* out) {
  const grasping::PickVerdict& verdict = pick.verdict;
  out->set_pickable(verdict.pickable);
  out->set_failure(grasping::PickFailureName(verdict.failure));
  out->set_detail(verdict.detail);
  if (!pick.covered_by_object_id.empty()) out->set_covered_by_object_id(pick.covered_by_object_id);
  if (!verdict.pickable) return;
  // The settled rotation is orthonormal to float precision only: a full inverse keeps
  // world_from_part x part_from_tool equal to world_from_tool.
  const Pose3 part_from_tool = world_from_part.inverse(Eigen::Affine) * verdict.world_from_tool;
  AddMatrix(part_from_tool, out->mutable_part_from_tool());
  AddVector(part_from_tool.linear().col(2), out->mutable_approach());
  AddMatrix(verdict.world_from_tool, out->mutable_world_from_tool());
  for (Eigen::Index j = 0; j < verdict.joint_positions.size(); ++j) out->add_joint_positions(verdict.joint_positions[j]);
}

void PicksSummary(const service::BinPicks& picks, v1::BinReport* out) {
  v1::BinReportPicks* summary = out->mutable_picks();
  summary->set_mount_id(picks.mount_id);
  summary->set_gripper(picks.gripper);
  uint32_t pickable = 0;
  for (const service::BinPartPick& part : picks.parts) pickable += part.verdict.pickable ? 1 : 0;
  summary->set_pickable(pickable);
  summary->set_parts_checked(static_cast<uint32_t>(picks.parts.size()));
  summary->set_grasps_generated(static_cast<uint32_t>(picks.grasps_generated));
  summary->set_elapsed_s(picks.elapsed_s);
}

void Parts(const service::BinFillPlan& plan, const service::BinFillReport& report, v1::BinReport* out) {
  const physics::FillResult& result = *report.result;
  std::map<std::string, const service::BinPartPick*> pick_of;
  if (report.picks) {
    for (const service::BinPartPick& pick : report.picks->parts) pick_of[pick.object_id] = &pick;
  }
  for (size_t i = 0; i < result.parts.size(); ++i) {
    const physics::PlacedPart& placed = result.parts[i];
    v1::BinReportPart* part = out->add_parts();
    part->set_type(static_cast<uint32_t>(placed.type));
    part->set_name(plan.parts[placed.type].name);
    part->set_instance(static_cast<uint32_t>(placed.instance));
    part->set_mesh_id(plan.request.parts[placed.type].mesh_id);
    part->set_source_unit(service::UnitName(plan.meshes[placed.type].source_unit));
    part->set_scale(plan.request.parts[placed.type].scale);
    if (report.placement) {
      const store::ObjectRecord& object = report.placement->parts[i];
      part->set_object_id(object.object_id);
      part->set_instance_id(object.instance_id);
      part->set_label(object.label);
      if (const auto pick = pick_of.find(object.object_id); pick != pick_of.end()) {
        Pick(*pick->second, placed.world_from_part, part->mutable_pick());
      }
    } else {
      part->set_label(service::PartLabel(plan.parts[placed.type].name, placed.instance));
    }
    AddMatrix(placed.world_from_part, part->mutable_world_from_part());
  }
  for (const physics::PlacedPart& placed : result.outside) {
    v1::BinReportOutside* part = out->add_outside();
    part->set_type(static_cast<uint32_t>(placed.type));
    part->set_name(plan.parts[placed.type].name);
    part->set_instance(static_cast<uint32_t>(placed.instance));
  }
}

void Result(const physics::FillResult& result, v1::BinReport* out) {
  out->set_end(physics::FillEndName(result.end));
  out->set_end_message(result.message);
  out->set_spawned(static_cast<uint32_t>(result.spawned));
  out->set_in_bin(static_cast<uint32_t>(result.parts.size()));
  out->set_simulated_s(result.simulated_s);
  out->set_steps(static_cast<uint32_t>(result.steps));
  out->set_max_part_part_penetration_m(result.max_part_part_penetration_m);
  out->set_max_part_bin_penetration_m(result.max_part_bin_penetration_m);
  const physics::MeshOverlaps& overlap = result.mesh_overlap;
  v1::BinReportMeshOverlap* mesh = out->mutable_mesh_overlap();
  mesh->set_max_part_part_m(overlap.max_part_part_m);
  mesh->set_p95_part_part_m(overlap.p95_part_part_m);
  mesh->set_overlapping_pairs(static_cast<uint32_t>(overlap.overlapping_pairs));
  mesh->set_max_part_bin_m(overlap.max_part_bin_m);
  mesh->set_resolution_m(overlap.resolution_m);
  mesh->set_moved_parts(static_cast<uint32_t>(overlap.moved_parts));
  mesh->set_max_move_m(overlap.max_move_m);
  mesh->set_rounds(static_cast<uint32_t>(overlap.rounds));
  out->set_setup_wall_s(result.setup_wall_s);
  out->set_step_wall_s(result.step_wall_s);
}

}  // namespace

v1::BinReport BinReportMessage(const service::BinFillPlan& plan, const service::BinFillReport& report) {
  v1::BinReport out;
  out.set_job_id(report.job_id);
  out.set_name(plan.request.name);
  out.set_scene_id(plan.request.scene_id);
  out.set_state(store::JobStateName(report.state));
  out.set_message(report.message);
  const physics::FillOptions& options = plan.request.options;
  out.set_seed(static_cast<double>(options.seed));
  v1::BinReportPhysics* physics = out.mutable_physics();
  physics->set_max_simulated_s(options.max_simulated_s);
  physics->set_time_step_s(options.time_step_s);
  physics->set_settle_move_m(options.settle_move_m);
  physics->set_settle_turn_rad(options.settle_turn_rad);
  physics->set_settle_steps(static_cast<uint32_t>(options.settle_steps));
  out.set_applied(report.placement.has_value());
  if (report.placement) out.set_scene_revision(static_cast<double>(report.placement->revision));
  Bin(plan, report, out.mutable_bin());
  Types(plan, &out);
  out.set_parts_asked(static_cast<uint32_t>(plan.parts_total()));
  if (report.result) {
    Result(*report.result, &out);
    Parts(plan, report, &out);
  }
  if (report.picks) PicksSummary(*report.picks, &out);
  return out;
}

}  // namespace vscan::api
