#pragma once
// The files at a dataset's root that describe it as a whole: dataset.json (layout version and
// plan), written by every shard as it starts, and scenes.json (the index), written by the merge.

#include <filesystem>
#include <string>

#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

std::string DatasetManifestJson(const DatasetPlan& plan);

// Every scene of the plan in order with its bin, seed, sensor and the CRC-32 of its record.
std::string SceneIndexJson(const DatasetPlan& plan, const std::vector<uint32_t>& record_crc32);

// Writes root/relative with bytes when it is absent (through a temporary file named after the
// writer, so shards starting together do not collide); when present it must hold the same bytes,
// else FailedPrecondition: the root belongs to another plan.
Status EnsureRootFile(const std::filesystem::path& root, const std::string& relative, const std::string& bytes,
                      const std::string& writer);

}  // namespace vscan::service::dataset
