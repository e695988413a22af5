#pragma once
// A BOP results file scored against a whole finished dataset as bop_toolkit's evaluation does it
// (docs/LOCALIZATION.md, "Scoring a dataset"): per image, the estimates of each object cut to
// its best-scored n (n its valid true instances, visib_fract >= 0.1) and matched by ScoreScan
// (ADD(-S) at 10% of the diameter, MSSD at 0.05..0.5); the matches pooled over the dataset,
// overall, per obj_id and per scene.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "service/datasets/dataset_score_tally.h"
#include "service/datasets/dataset_truth.h"
#include "service/datasets/format/bop_results_csv.h"
#include "service/localization/grasp_scoring.h"
#include "vscan/common/status.h"

namespace vscan::service {

// The most vertex operations one scoring may take (some 100 s on one core of a 2-core VM), counted
// as ScorePoses counts them (vertices x (symmetry transforms + 1, or + 20 for ADD-S) per pair of a
// kept estimate and a valid true instance).
inline constexpr uint64_t kMaxDatasetScoringWork = 30'000'000'000;
// Images without ground truth named in the answer (the count covers them all).
inline constexpr size_t kMaxIgnoredImagesNamed = 10;
// Scenes given figures of their own (those with the lowest ids); the rest count overall and per object.
inline constexpr uint32_t kMaxScenesScored = 10000;

struct DatasetScoringOptions {
  const std::atomic<bool>* cancel = nullptr;  // polled between images and pairs: CANCELLED
  uint64_t max_work = kMaxDatasetScoringWork;
  uint32_t max_scenes = kMaxScenesScored;
  // Set: each match is also judged by its planned grasp (models and poses taken in metres, up in
  // the camera frame); each obj_id's grasp generation and each kept estimate's grasp count in
  // max_work (GraspPreparationWork, GraspJudgementWork).
  std::optional<GraspScoring> grasp;
};

struct DatasetScore {
  DatasetScoreTally tally{0};
  std::map<uint32_t, DatasetModel> models;
  uint64_t scene_count = 0;
  uint64_t images = 0;          // images of the dataset (with or without estimates)
  uint64_t true_instances = 0;  // every ground-truth object, valid or not (BOP's gt_count)
  uint64_t rows = 0;            // estimates read
  // Rows for a (scene_id, im_id) the dataset does not have: left out, as bop_toolkit leaves out
  // estimates of images that are not targets.
  uint64_t ignored_rows = 0;
  std::vector<std::pair<uint32_t, uint32_t>> ignored_images;  // the first kMaxIgnoredImagesNamed
  std::vector<double> mssd_thresholds;
  double add_threshold = 0;
  double min_visible_fraction = 0;
  uint64_t work = 0;  // vertex operations spent
};

// field names the results in errors. INVALID_ARGUMENT naming field, the line and obj_id for an
// obj_id the dataset has no model of (checked before anything is scored); FAILED_PRECONDITION
// for an unfinished dataset; DATA_LOSS for damaged dataset files; RESOURCE_EXHAUSTED naming field
// once the work passes options.max_work; CANCELLED once options.cancel is set.
StatusOr<DatasetScore> ScoreDatasetResults(const std::filesystem::path& root,
                                           std::span<const dataset::BopResultRow> rows,
                                           const DatasetScoringOptions& options, std::string_view field);

}  // namespace vscan::service
