#include "service/datasets/format/dataset_merge.h"

#include <set>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/dataset_manifest.h"
#include "service/datasets/format/durable_file.h"
#include "service/datasets/format/scene_record.h"

namespace vscan::service::dataset {
namespace {

Status CheckManifest(const std::filesystem::path& root, const DatasetPlan& plan) {
  StatusOr<std::string> manifest = ReadWholeFile(root / kManifestFile);
  if (!manifest.ok()) return FailedPrecondition((root / kManifestFile).string() + " is missing: no shard ran here");
  if (*manifest != DatasetManifestJson(plan)) {
    return FailedPrecondition((root / kManifestFile).string() + " belongs to another plan");
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(root / kModelsInfoFile, ec)) {
    return FailedPrecondition((root / kModelsInfoFile).string() + " is missing");
  }
  return Status::Ok();
}

// Names under scenes/ that are not scenes of the plan, and the plan's scenes that are absent.
Status CheckSceneNames(const std::filesystem::path& root, const DatasetPlan& plan) {
  std::set<std::string> present;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(root / kScenesDir, ec)) {
    present.insert(entry.path().filename().string());
  }
  if (ec) return FailedPrecondition("cannot list " + (root / kScenesDir).string() + ": " + ec.message());
  std::string missing;
  uint64_t missing_count = 0;
  for (uint64_t id = 0; id < SceneCount(plan); ++id) {
    if (present.erase(SixDigits(id)) == 1) continue;
    if (++missing_count <= 10) missing += (missing.empty() ? "" : ", ") + SixDigits(id);
  }
  if (!present.empty()) {
    return FailedPrecondition((root / kScenesDir).string() + " holds " + *present.begin() +
                              ", which is no scene of the plan (a partial scene means a shard did not finish)");
  }
  if (missing_count > 0) {
    return FailedPrecondition(std::to_string(missing_count) + " of " + std::to_string(SceneCount(plan)) +
                              " scenes are missing: " + missing + (missing_count > 10 ? ", ..." : ""));
  }
  return Status::Ok();
}

StatusOr<uint32_t> CheckScene(const std::filesystem::path& root, const DatasetPlan& plan, uint64_t id) {
  const std::filesystem::path dir = SceneDir(root, id);
  StatusOr<std::string> record = ReadWholeFile(dir / kSceneRecordFile);
  if (!record.ok()) return DataLoss((dir / kSceneRecordFile).string() + " is missing");
  ASSIGN_OR_RETURN(const std::vector<SceneFileEntry> files, ListSceneFiles(dir));
  if (*record != SceneRecordJson(plan, SceneAt(plan, id), files)) {
    return DataLoss(dir.string() + " does not match its record: a file is missing, extra or changed, or the scene "
                                   "belongs to another plan");
  }
  return Crc32(*record);
}

}  // namespace

Status MergeDataset(const std::filesystem::path& root, const DatasetPlan& plan) {
  RETURN_IF_ERROR(CheckPlan(plan));
  RETURN_IF_ERROR(CheckManifest(root, plan));
  RETURN_IF_ERROR(CheckSceneNames(root, plan));
  std::vector<uint32_t> record_crc32;
  for (uint64_t id = 0; id < SceneCount(plan); ++id) {
    ASSIGN_OR_RETURN(const uint32_t crc, CheckScene(root, plan, id));
    record_crc32.push_back(crc);
  }
  return ReplaceFileDurably(root / kSceneIndexFile, SceneIndexJson(plan, record_crc32), ".tmp-merge");
}

}  // namespace vscan::service::dataset
