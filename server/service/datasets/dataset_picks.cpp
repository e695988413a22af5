#include "service/datasets/dataset_picks.h"

#include <chrono>
#include <string>

#include "service/robot/grasp_reach.h"

namespace vscan::service {
namespace {

// The API's names of the failures (picking.proto's PickFailure).
const char* FailureApiName(grasping::PickFailure failure) {
  switch (failure) {
    case grasping::PickFailure::kNone: return "PICK_FAILURE_UNSPECIFIED";
    case grasping::PickFailure::kCovered: return "PICK_FAILURE_COVERED";
    case grasping::PickFailure::kNoGrasp: return "PICK_FAILURE_NO_GRASP";
    case grasping::PickFailure::kGripperCollision: return "PICK_FAILURE_GRIPPER_COLLISION";
    case grasping::PickFailure::kUnreachable: return "PICK_FAILURE_UNREACHABLE";
    case grasping::PickFailure::kArmCollision: return "PICK_FAILURE_ARM_COLLISION";
  }
  return "PICK_FAILURE_UNSPECIFIED";
}

std::string Named(const grasping::PileItem& item, const std::vector<FillPart>& parts) {
  return item.fixture ? std::string("the bin") : "instance " + std::to_string(parts[item.index].instance_id);
}

}  // namespace

StatusOr<std::shared_ptr<const DatasetPickSetup>> PrepareDatasetPicks(
    const dataset::DatasetPicks& plan, std::shared_ptr<const robot::KinematicChain> robot_chain,
    const std::vector<dataset::PartModel>& parts, const std::vector<uint64_t>& parts_per_bin) {
  for (const dataset::PartModel& part : parts) {
    const Status work = grasping::CheckGraspWork(part.mesh.triangles.size(), plan.gripper, plan.grasp_options);
    if (!work.ok()) return work.WithFieldPrefix("picks");
  }
  for (const uint64_t count : parts_per_bin) {
    const double iterations =
        double(count) * double(plan.pick_options.max_reach_checks) * 2 * double(plan.ik_iterations);
    if (iterations > dataset::kMaxIkIterationsPerScene) {
      return ResourceExhausted("picks.pick_options.max_reach_checks",
                               "parts x max_reach_checks x 2 x ik_iterations = " + std::to_string(uint64_t(iterations)) +
                                   " solver iterations a scene; at most " +
                                   std::to_string(uint64_t(dataset::kMaxIkIterationsPerScene)));
    }
  }
  auto setup = std::make_shared<DatasetPickSetup>();
  setup->plan = plan;
  setup->chain = plan.flange_from_tool
                     ? std::make_shared<const robot::KinematicChain>(robot_chain->WithTool(*plan.flange_from_tool))
                     : std::move(robot_chain);
  setup->options = plan.pick_options;
  if (setup->options.sweep.body_length_m == 0) {
    setup->options.sweep.body_length_m = setup->chain->tip_from_tool().translation().norm();
  }
  for (const dataset::PartModel& part : parts) {
    setup->meshes.push_back(std::make_shared<const TriangleMesh>(part.mesh));
    StatusOr<std::vector<grasping::Grasp>> grasps = grasping::GenerateGrasps(part.mesh, plan.gripper, plan.grasp_options);
    if (!grasps.ok()) {
      return grasps.status().WithFieldPrefix("picks: part type " + std::to_string(part.obj_id));
    }
    setup->grasps.push_back(std::move(*grasps));
  }
  return std::shared_ptr<const DatasetPickSetup>(std::move(setup));
}

StatusOr<std::vector<dataset::PartPickRecord>> CheckFillPicks(const DatasetPickSetup& picks,
                                                              const std::vector<FillPart>& parts,
                                                              const std::vector<grasping::PlacedMesh>& fixtures,
                                                              const std::atomic<bool>* cancel) {
  std::vector<dataset::PartPickRecord> out;
  if (parts.empty()) return out;
  grasping::Pile pile;
  pile.fixtures = fixtures;
  for (const FillPart& part : parts) {
    const size_t type = part.obj_id - 1;
    if (part.obj_id == 0 || type >= picks.meshes.size()) {
      return Internal("instance " + std::to_string(part.instance_id) + " has no part type " + std::to_string(part.obj_id));
    }
    pile.parts.push_back({type, picks.meshes[type], part.world_from_part});
  }
  robot_registry::Placement placement;
  placement.frame_from_base = picks.plan.world_from_base;
  robot_registry::IkSettings settings;
  settings.max_iterations = static_cast<int>(picks.plan.ik_iterations);
  // Never the end of a solve: the iterations are.
  settings.time_budget = std::chrono::hours(1);
  const grasping::ReachCheck reach = KinematicReach(picks.chain, placement, picks.plan.gripper, settings);
  ASSIGN_OR_RETURN(std::vector<grasping::PickVerdict> verdicts,
                   grasping::CheckPicks(pile, picks.grasps, picks.plan.gripper, picks.options, reach, cancel));
  for (size_t i = 0; i < verdicts.size(); ++i) {
    const grasping::PickVerdict& verdict = verdicts[i];
    dataset::PartPickRecord record;
    record.instance_id = parts[i].instance_id;
    record.pickable = verdict.pickable;
    record.failure = FailureApiName(verdict.failure);
    record.detail = verdict.detail;
    if (verdict.pickable) {
      record.grasp = verdict.grasp;
      record.world_from_tool = verdict.world_from_tool;
    }
    if (verdict.covered_by) {
      if (verdict.covered_by->fixture) {
        record.covered_by_bin = true;
      } else {
        record.covered_by_instance = parts[verdict.covered_by->index].instance_id;
      }
      record.detail = Named(*verdict.covered_by, parts) + " lies on it";
    }
    if (verdict.failure == grasping::PickFailure::kGripperCollision && verdict.blocked_by) {
      record.detail = "the gripper's way in meets " + Named(*verdict.blocked_by, parts);
    }
    out.push_back(std::move(record));
  }
  return out;
}

}  // namespace vscan::service
