#pragma once
// The picks section of a dataset plan read from YAML:
//   picks:
//     robot_id: rob_4c1d                       # a stored robot
//     base: {xyz: [0.45, 0, 0], rpy_deg: [0, 0, 180]}  # world_from_base; or {xyz, quat: [w, x, y, z]}
//     tool: {xyz: [0, 0, 0.08]}                # optional flange_from_tool
//     gripper: {suction: {diameter: 0.012}}    # or {jaws: {max_opening: 0.04, ...}}
//     grasp_options: {max_grasps: 200, seed: 1, candidates: 1000, surface_samples: 20000}
//     pick_options: {approach_distance: 0.05, max_approach_tilt_deg: 60, cover_distance: 0.002,
//                    max_reach_checks: 8, body_length: 0.08, ik_iterations: 2000}
// The gripper's and options' names are picking.proto's and the bin fill plan's.

#include "service/datasets/format/dataset_picks_plan.h"
#include "vscan/common/status.h"
#include "vscan/plan/yaml_reader.h"

namespace vscan::service::dataset {

// INVALID_ARGUMENT "source:line: picks.<key>: what" for an unknown key, a missing robot_id,
// base or gripper, a non-finite or non-rigid pose, or a value grasping::ValidateGripper,
// ValidateGraspOptions or ValidatePickOptions refuses (named as the plan names it).
StatusOr<DatasetPicks> ReadDatasetPicks(const plan::YamlReader& yaml, const plan::YamlAt& at);

}  // namespace vscan::service::dataset
