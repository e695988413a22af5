#pragma once
// A dataset plan from its YAML file (docs/DATASETS.md, "The plan file"):
//   name: demo
//   bins: [small-bin, large-bin]
//   seeds: {first: 100, count: 8}   # or a list: [3, 5, 8]
//   sensors: [zivid-2-m70]
//   depth_scale_mm: 0.1             # optional

#include <string>
#include <string_view>

#include "service/dataset/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// InvalidArgument names `source` and the offending key; the plan is checked (CheckPlan).
StatusOr<DatasetPlan> ParseDatasetPlanYaml(std::string_view text, const std::string& source);

}  // namespace vscan::service::dataset
