#pragma once
// A dataset plan from its YAML file (docs/DATASETS.md, "The plan file"):
//   name: demo
//   bins: [small-bin, large-bin]    # or mappings describing each fill: name, box, parts
//   seeds: {first: 100, count: 8}   # or a list: [3, 5, 8]
//   sensors: [kinect-v2-class]      # preset names, or {name, preset, width, height}
//   depth_scale_mm: 0.1             # optional
//   camera_height_m: 0.6            # optional
//   views: {count: 8, cone_deg: 30, distance_m: [0.5, 0.8]}  # optional: images per scene
//   fail_on_underfilled_bin: false  # optional
//   picks: {robot_id, base, gripper, ...}  # optional: scene_pickable.json (dataset_picks_yaml.h)

#include <string>
#include <string_view>

#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// InvalidArgument names `source` and the offending key; the plan is checked (CheckPlan).
StatusOr<DatasetPlan> ParseDatasetPlanYaml(std::string_view text, const std::string& source);

}  // namespace vscan::service::dataset
