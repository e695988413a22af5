#pragma once
// Pools the per-image scores of a dataset (localization::ScoreScan, one call per image) as BOP's
// score.calc_localization_scores does: recall = matched valid true instances / valid true
// instances, summed over every image, overall, per object (obj_id) and per scene. The MSSD
// average recall is the mean over its thresholds of the pooled recall at each.

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "localization/bop_scoring.h"
#include "service/localization/grasp_scoring.h"

namespace vscan::service {

struct RecallCounts {
  uint64_t valid_instances = 0;  // BOP's targets
  uint64_t estimates = 0;        // results rows for images of the dataset
  uint64_t add_correct = 0;
  std::vector<uint64_t> mssd_correct;  // per threshold
  uint64_t grasp_holds = 0;             // with a gripper: matches whose planned grasp holds

  // Unset without valid instances (BOP's calc_recall gives 0 there).
  std::optional<double> AddRecall() const;
  std::optional<double> MssdAverageRecall() const;
  std::vector<double> MssdRecalls() const;  // empty without valid instances
  // grasp_holds / valid_instances; unset without valid instances.
  std::optional<double> GraspSuccess() const;
};

class DatasetScoreTally {
 public:
  // Scenes with ids from max_scenes on are pooled overall and per object only (a dataset may
  // hold a million scenes; an answer lists a bounded number).
  explicit DatasetScoreTally(size_t mssd_thresholds, uint32_t max_scenes = UINT32_MAX)
      : thresholds_(mssd_thresholds), max_scenes_(max_scenes) {
    overall_.mssd_correct.assign(thresholds_, 0);
  }

  // One image's score; its parts' part_id are obj_ids and its MSSD recalls are at the tally's
  // thresholds.
  // grasps, when given, is JudgeScanGrasps' answer for the same image.
  void AddImage(uint32_t scene_id, const localization::ScanScore& image, const ScanGraspScore* grasps = nullptr);
  // Estimates read for an object in an image of scene_id (before the top-n cut).
  void AddEstimates(uint32_t scene_id, uint32_t obj_id, uint64_t count);
  // Makes the object and scene appear even when they hold nothing (BOP lists every obj_id).
  void AddObject(uint32_t obj_id) { Entry(objects_, obj_id); }
  void AddScene(uint32_t scene_id) {
    if (scene_id < max_scenes_) Entry(scenes_, scene_id);
  }

  const RecallCounts& overall() const { return overall_; }
  const std::map<uint32_t, RecallCounts>& objects() const { return objects_; }
  const std::map<uint32_t, RecallCounts>& scenes() const { return scenes_; }

 private:
  RecallCounts& Entry(std::map<uint32_t, RecallCounts>& map, uint32_t id);

  size_t thresholds_;
  uint32_t max_scenes_;
  RecallCounts overall_;
  std::map<uint32_t, RecallCounts> objects_, scenes_;
};

}  // namespace vscan::service
