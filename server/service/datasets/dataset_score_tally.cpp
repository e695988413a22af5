#include "service/datasets/dataset_score_tally.h"

#include <cmath>

namespace vscan::service {

std::optional<double> RecallCounts::AddRecall() const {
  if (valid_instances == 0) return std::nullopt;
  return static_cast<double>(add_correct) / static_cast<double>(valid_instances);
}

std::vector<double> RecallCounts::MssdRecalls() const {
  std::vector<double> recalls;
  if (valid_instances == 0) return recalls;
  for (const uint64_t correct : mssd_correct) {
    recalls.push_back(static_cast<double>(correct) / static_cast<double>(valid_instances));
  }
  return recalls;
}

std::optional<double> RecallCounts::MssdAverageRecall() const {
  const std::vector<double> recalls = MssdRecalls();
  if (recalls.empty()) return std::nullopt;
  double sum = 0;
  for (const double r : recalls) sum += r;
  return sum / static_cast<double>(recalls.size());
}

std::optional<double> RecallCounts::GraspSuccess() const {
  if (valid_instances == 0) return std::nullopt;
  return static_cast<double>(grasp_holds) / static_cast<double>(valid_instances);
}

RecallCounts& DatasetScoreTally::Entry(std::map<uint32_t, RecallCounts>& map, uint32_t id) {
  RecallCounts& counts = map[id];
  if (counts.mssd_correct.size() != thresholds_) counts.mssd_correct.assign(thresholds_, 0);
  return counts;
}

void DatasetScoreTally::AddImage(uint32_t scene_id, const localization::ScanScore& image,
                                 const ScanGraspScore* grasps) {
  RecallCounts* scene = scene_id < max_scenes_ ? &Entry(scenes_, scene_id) : nullptr;
  for (size_t p = 0; p < image.parts.size(); ++p) {
    const localization::PartScore& part = image.parts[p];
    const uint64_t holds = grasps != nullptr && p < grasps->parts.size() ? grasps->parts[p].holds : 0;
    RecallCounts& object = Entry(objects_, part.part_id);
    for (RecallCounts* counts : {&overall_, &object, scene}) {
      if (counts == nullptr) continue;
      counts->valid_instances += part.valid_instances;
      counts->add_correct += part.add_correct;
      counts->grasp_holds += holds;
      // ScoreScan gives the recall at each threshold; matched instances = recall x valid, exactly.
      for (size_t t = 0; t < part.mssd_recalls.size() && t < thresholds_; ++t) {
        counts->mssd_correct[t] +=
            static_cast<uint64_t>(std::llround(part.mssd_recalls[t] * static_cast<double>(part.valid_instances)));
      }
    }
  }
}

void DatasetScoreTally::AddEstimates(uint32_t scene_id, uint32_t obj_id, uint64_t count) {
  overall_.estimates += count;
  Entry(objects_, obj_id).estimates += count;
  if (scene_id < max_scenes_) Entry(scenes_, scene_id).estimates += count;
}

}  // namespace vscan::service
