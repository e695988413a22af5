#pragma once
// Dataset runs without a server, as Kubernetes pods run them: one shard of a plan file into a
// directory, and the merge that checks every shard finished (docs/DATASETS.md, "Shards").

#include <cstdint>
#include <filesystem>
#include <functional>

#include "service/datasets/dataset_job_setup.h"
#include "service/datasets/format/dataset_run.h"

namespace vscan::service {

// Reads and checks the plan (mesh files relative to its directory), then RunDatasetShard; a plan's
// returned_light is resolved as the server's dataset job resolves it.
StatusOr<dataset::DatasetProgress> RunDatasetShardFromFile(
    const std::filesystem::path& plan_file, const std::filesystem::path& root, uint32_t shard_index,
    uint32_t shard_count, const std::function<void(const dataset::DatasetProgress&)>& on_progress,
    const DatasetLightResolver& resolve_light = {});

// Reads the plan, then MergeDataset.
Status MergeDatasetFromFile(const std::filesystem::path& plan_file, const std::filesystem::path& root);

// The plan file parsed; InvalidArgument names the file and the key, NotFound a missing file.
StatusOr<dataset::DatasetPlan> ReadDatasetPlanFile(const std::filesystem::path& plan_file);

}  // namespace vscan::service
