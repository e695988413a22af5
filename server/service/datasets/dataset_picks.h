#pragma once
// A dataset plan's picks in engine terms, and the check each settled fill gets: grasps generated
// once per part type, then grasping::CheckPicks on the fill's parts (the bin and the table under
// it are fixtures) with the robot's inverse kinematics as the reach test (KinematicReach: no link
// collisions). Iteration-bounded, so a scene gets the same verdicts on every run.

#include <atomic>
#include <memory>
#include <vector>

#include "grasping/grasp_generation.h"
#include "grasping/pick_checks.h"
#include "robot/chain.h"
#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct DatasetPickSetup {
  dataset::DatasetPicks plan;
  std::shared_ptr<const robot::KinematicChain> chain;  // with the plan's tool, or the robot's own
  grasping::PickOptions options;                       // body length resolved
  std::vector<std::shared_ptr<const TriangleMesh>> meshes;  // per part type (obj_id - 1), metres
  std::vector<std::vector<grasping::Grasp>> grasps;         // per part type, best first
};

// RESOURCE_EXHAUSTED naming "picks.grasp_options.candidates" when a part type's grasp search would
// pass the engine's bound, or "picks.pick_options.max_reach_checks" when a bin's parts x
// max_reach_checks x 2 solves x ik_iterations passes dataset::kMaxIkIterationsPerScene; then the
// grasps of every part type. parts: the plan's part models; parts_per_bin: each bin's parts asked for.
StatusOr<std::shared_ptr<const DatasetPickSetup>> PrepareDatasetPicks(
    const dataset::DatasetPicks& plan, std::shared_ptr<const robot::KinematicChain> robot_chain,
    const std::vector<dataset::PartModel>& parts, const std::vector<uint64_t>& parts_per_bin);

// A placed part of a fill.
struct FillPart {
  uint32_t instance_id = 0;
  uint32_t obj_id = 0;  // 1-based part type
  Pose3 world_from_part = Pose3::Identity();
};

// One record per part, in order. CANCELLED once *cancel is set.
StatusOr<std::vector<dataset::PartPickRecord>> CheckFillPicks(const DatasetPickSetup& picks,
                                                              const std::vector<FillPart>& parts,
                                                              const std::vector<grasping::PlacedMesh>& fixtures,
                                                              const std::atomic<bool>* cancel);

}  // namespace vscan::service
