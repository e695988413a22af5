#include "service/datasets/format/dataset_run.h"

#include <algorithm>
#include <deque>
#include <future>
#include <optional>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/dataset_manifest.h"
#include "service/datasets/format/dataset_merge.h"
#include "service/datasets/format/model_ply.h"
#include "service/datasets/format/models_info.h"
#include "service/datasets/format/durable_file.h"
#include "service/datasets/format/scene_json.h"
#include "service/datasets/format/scene_writer.h"

namespace vscan::service::dataset {
namespace {

// At most this many views of one scene are captured at once (each frame holds its cloud and images).
constexpr size_t kViewsInFlight = 4;

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

size_t FramesInFlight(size_t frames_ahead, uint32_t views_per_scene) {
  return frames_ahead == 0 ? 1 : frames_ahead + std::min<size_t>(views_per_scene, kViewsInFlight);
}

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
  const uint32_t views = plan.views.count;
  // Frames in flight, oldest first: (scene, view) in order, each written once it and every frame
  // before it are done.
  struct Pending {
    uint64_t scene_id;
    uint32_t view;
    std::future<StatusOr<DatasetFrame>> frame;
  };
  std::deque<Pending> in_flight;
  const uint64_t frame_count = uint64_t{missing.size()} * views;
  uint64_t next = 0;
  std::optional<SceneWriter> writer;
  // The views of a scene wait for its one fill: a window of a scene's views beside the frames
  // ahead lets the next scene's fill start while this one's views are scanned.
  const size_t window = FramesInFlight(run.frames_ahead, views);
  while (next < frame_count || !in_flight.empty()) {
    while (next < frame_count && in_flight.size() < window) {
      if (run.stop_requested && run.stop_requested()) return Cancelled("the dataset run was stopped");
      const uint64_t id = missing[next / views];
      const auto view = static_cast<uint32_t>(next % views);
      ++next;
      const SceneKey key = SceneAt(plan, id);
      const auto policy = run.frames_ahead == 0 ? std::launch::deferred : std::launch::async;
      in_flight.push_back({id, view, std::async(policy, [&source, key, view] { return source(key, view); })});
    }
    const uint64_t id = in_flight.front().scene_id;
    const uint32_t view = in_flight.front().view;
    StatusOr<DatasetFrame> frame = in_flight.front().frame.get();
    in_flight.pop_front();
    const std::string field = "scenes[" + std::to_string(id) + "]" + (views > 1 ? ".views[" + std::to_string(view) + "]" : "");
    if (!frame.ok()) return frame.status().WithFieldPrefix(field);
    const SceneKey key = SceneAt(plan, id);
    if (view == 0) {
      if (frame->parts_placed < frame->parts_planned) {
        if (plan.fail_on_underfilled_bin) {
          return FailedPrecondition("scenes[" + std::to_string(id) + "]: the bin took " +
                                    std::to_string(frame->parts_placed) + " of " + std::to_string(frame->parts_planned) +
                                    " parts and the plan sets fail_on_underfilled_bin");
        }
        progress.underfilled.push_back(id);
      }
      StatusOr<SceneWriter> begun = SceneWriter::Begin(root, plan, key);
      if (!begun.ok()) return begun.status().WithFieldPrefix("scenes[" + std::to_string(id) + "]");
      writer.emplace(std::move(*begun));
    }
    Status written = writer->AddView(*frame);
    // Every scene of a sensor has its intrinsics; the first one a shard writes publishes them.
    if (written.ok() && view == 0) {
      written = EnsureRootFile(root, CameraFileName(plan.sensors, key.sensor_index),
                               CameraParamsJson(*frame, plan.depth_scale_mm), "shard-" + std::to_string(run.shard_index));
    }
    if (!written.ok()) return written.WithFieldPrefix(field);
    if (view + 1 < views) continue;
    written = writer->Finish();
    writer.reset();
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
