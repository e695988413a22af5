#pragma once
// The step after every shard: checks that the root holds exactly the plan's scenes, each complete
// and intact, then writes the index (scenes.json). The bytes do not depend on how the scenes were
// sharded.

#include <filesystem>

#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// FailedPrecondition when dataset.json belongs to another plan, models_info.json or a scene is
// missing (the message names up to ten missing scene ids and how many there are), or train_pbr/
// holds anything else (a partial directory of an unfinished shard, an unknown name). DataLoss when
// a scene's files differ from its record (missing, extra or changed bytes) or the record names
// another scene of the plan.
Status MergeDataset(const std::filesystem::path& root, const DatasetPlan& plan);

}  // namespace vscan::service::dataset
