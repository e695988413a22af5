#pragma once
// A scene's record (scene_files.json): which scene of the plan it is and every file it holds with
// its size and CRC-32. The writer records what it wrote; the merge lists what is on disk, renders
// the record again and compares bytes, so a missing, extra or damaged file shows.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

struct SceneFileEntry {
  std::string path;  // relative to the scene directory, '/'-separated
  uint64_t bytes = 0;
  uint32_t crc32 = 0;
};

uint32_t Crc32(std::string_view bytes);

// Every regular file under dir except the record itself, sorted by path; FailedPrecondition for
// anything that is neither a regular file nor a directory.
StatusOr<std::vector<SceneFileEntry>> ListSceneFiles(const std::filesystem::path& dir);

std::string SceneRecordJson(const DatasetPlan& plan, const SceneKey& key, const std::vector<SceneFileEntry>& files);

}  // namespace vscan::service::dataset
