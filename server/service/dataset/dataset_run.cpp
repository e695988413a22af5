#include "service/dataset/dataset_run.h"

#include <algorithm>
#include <deque>
#include <future>

#include "service/dataset/dataset_layout.h"
#include "service/dataset/dataset_manifest.h"
#include "service/dataset/dataset_merge.h"
#include "service/dataset/model_ply.h"
#include "service/dataset/models_info.h"
#include "service/dataset/durable_file.h"
#include "service/dataset/scene_json.h"
#include "service/dataset/scene_writer.h"

namespace vscan::service::dataset {
namespace {

Status PrepareRoot(const std::filesystem::path& root, const DatasetPlan& plan, const std::vector<PartModel>& parts,
                   uint32_t shard_index) {
  std::error_code ec;
  std::filesystem::create_directories(root / kScenesDir, ec);
  if (ec) return Internal("cannot create " + (root / kScenesDir).string() + ": " + ec.message());
  const std::string writer = "shard-" + std::to_string(shard_index);
  RETURN_IF_ERROR(EnsureRootFile(root, kManifestFile, DatasetManifestJson(plan), writer));
  ASSIGN_OR_RETURN(const std::string models_info, ModelsInfoJson(parts));
  RETURN_IF_ERROR(EnsureRootFile(root, kModelsInfoFile, models_info, writer));
  for (const PartModel& part : parts) {
    ASSIGN_OR_RETURN(const std::string ply, EncodeModelPly(part));
    RETURN_IF_ERROR(EnsureRootFile(root, ModelPlyPath(part.obj_id), ply, writer));
  }
  return Status::Ok();
}

}  // namespace

StatusOr<DatasetProgress> RunDatasetShard(const std::filesystem::path& root, const DatasetPlan& plan,
                                          const std::vector<PartModel>& parts, const FrameSource& source,
                                          const ShardRun& run) {
  RETURN_IF_ERROR(CheckPlan(plan));
  RETURN_IF_ERROR(CheckShard(run.shard_index, run.shard_count));
  RETURN_IF_ERROR(PrepareRoot(root, plan, parts, run.shard_index));
  DatasetProgress progress;
  std::vector<uint64_t> missing;
  for (const uint64_t id : ScenesOfShard(plan, run.shard_index, run.shard_count)) {
    ++progress.total;
    std::error_code ec;
    if (std::filesystem::exists(SceneDir(root, id), ec)) {
      ++progress.skipped;
      const StatusOr<std::string> fill = ReadWholeFile(SceneDir(root, id) / kSceneFillFile);
      if (fill.ok() && SceneFillSaysUnderfilled(*fill)) progress.underfilled.push_back(id);
      continue;
    }
    std::filesystem::remove_all(PartialSceneDir(root, id), ec);
    if (ec) return Internal("cannot remove " + PartialSceneDir(root, id).string() + ": " + ec.message());
    missing.push_back(id);
  }
  progress.done = progress.skipped;
  if (run.on_progress) run.on_progress(progress);
  // Frames in flight, oldest first; a frame is written once it and every frame before it are done.
  std::deque<std::pair<uint64_t, std::future<StatusOr<DatasetFrame>>>> in_flight;
  size_t next = 0;
  while (next < missing.size() || !in_flight.empty()) {
    while (next < missing.size() && in_flight.size() <= run.frames_ahead) {
      if (run.stop_requested && run.stop_requested()) return Cancelled("the dataset run was stopped");
      const uint64_t id = missing[next++];
      const SceneKey key = SceneAt(plan, id);
      const auto policy = run.frames_ahead == 0 ? std::launch::deferred : std::launch::async;
      in_flight.emplace_back(id, std::async(policy, [&source, key] { return source(key); }));
    }
    const uint64_t id = in_flight.front().first;
    StatusOr<DatasetFrame> frame = in_flight.front().second.get();
    in_flight.pop_front();
    if (!frame.ok()) return frame.status().WithFieldPrefix("scenes[" + std::to_string(id) + "]");
    if (frame->parts_placed < frame->parts_planned) {
      if (plan.fail_on_underfilled_bin) {
        return FailedPrecondition("scenes[" + std::to_string(id) + "]: the bin took " +
                                  std::to_string(frame->parts_placed) + " of " + std::to_string(frame->parts_planned) +
                                  " parts and the plan sets fail_on_underfilled_bin");
      }
      progress.underfilled.push_back(id);
    }
    const SceneKey key = SceneAt(plan, id);
    Status written = WriteScene(root, plan, key, *frame);
    // Every scene of a sensor has its intrinsics; the first one a shard writes publishes them.
    if (written.ok()) {
      written = EnsureRootFile(root, CameraFileName(plan.sensors, key.sensor_index),
                               CameraParamsJson(*frame, plan.depth_scale_mm), "shard-" + std::to_string(run.shard_index));
    }
    if (!written.ok()) return written.WithFieldPrefix("scenes[" + std::to_string(id) + "]");
    ++progress.written;
    ++progress.done;
    if (run.on_progress) run.on_progress(progress);
  }
  std::sort(progress.underfilled.begin(), progress.underfilled.end());
  return progress;
}

StatusOr<DatasetProgress> WriteDataset(const std::filesystem::path& root, const DatasetPlan& plan,
                                       const std::vector<PartModel>& parts, const FrameSource& source,
                                       const std::function<void(const DatasetProgress&)>& on_progress) {
  ShardRun run;
  run.on_progress = on_progress;
  ASSIGN_OR_RETURN(const DatasetProgress progress, RunDatasetShard(root, plan, parts, source, run));
  RETURN_IF_ERROR(MergeDataset(root, plan));
  return progress;
}

}  // namespace vscan::service::dataset
