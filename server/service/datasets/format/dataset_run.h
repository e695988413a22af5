#pragma once
// Runs the scenes of one shard of a plan into a dataset root, skipping scenes already written, so
// a restarted run picks up where it stopped. One process writing a whole dataset is shard 0 of 1
// followed by the merge (WriteDataset).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "service/datasets/format/dataset_frame.h"
#include "service/datasets/format/dataset_plan.h"
#include "vscan/common/status.h"

namespace vscan::service::dataset {

// Captures one view (0 .. views.count - 1) of one scene (bin fill under the seed, seen by the
// sensor). With ShardRun::frames_ahead > 0 it is called from several threads at once.
using FrameSource = std::function<StatusOr<DatasetFrame>(const SceneKey&, uint32_t view)>;

struct DatasetProgress {
  uint64_t total = 0;    // scenes of the shard
  uint64_t done = 0;     // skipped + written
  uint64_t skipped = 0;  // found complete when the run started
  uint64_t written = 0;  // written by this run
  // Scenes whose bin took fewer parts than planned (found or written), ids ascending.
  std::vector<uint64_t> underfilled;
};

struct ShardRun {
  uint32_t shard_index = 0;
  uint32_t shard_count = 1;
  // Called once after the finished scenes are counted, then after every scene written.
  std::function<void(const DatasetProgress&)> on_progress;
  // Asked before each scene; true stops the run with Cancelled (finished scenes stay).
  std::function<bool()> stop_requested;
  // Frames captured concurrently ahead of the one being written (a fill steps its physics on one
  // thread, so other cores fill the next bins), plus up to four views of a scene while its fill
  // runs; scenes are still written one by one, in order.
  size_t frames_ahead = 0;
};

// Frames a run holds at once (captured, not yet written): one when none are captured ahead, else
// the frames ahead plus up to four views of a scene.
size_t FramesInFlight(size_t frames_ahead, uint32_t views_per_scene);

// Writes dataset.json and models/models_info.json (or checks that they match), removes partial
// directories of this shard's scenes, then writes every missing scene of the shard in order.
StatusOr<DatasetProgress> RunDatasetShard(const std::filesystem::path& root, const DatasetPlan& plan,
                                          const std::vector<PartModel>& parts, const FrameSource& source,
                                          const ShardRun& run);

// The whole plan in one process: shard 0 of 1, then MergeDataset.
StatusOr<DatasetProgress> WriteDataset(const std::filesystem::path& root, const DatasetPlan& plan,
                                       const std::vector<PartModel>& parts, const FrameSource& source,
                                       const std::function<void(const DatasetProgress&)>& on_progress);

}  // namespace vscan::service::dataset
