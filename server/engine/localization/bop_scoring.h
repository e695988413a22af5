#pragma once
// Scores the part instances found in one scan against the true ones with the BOP benchmark's
// rules: recall of ADD(-S) at 10% of the diameter and the MSSD average recall over thresholds of
// 5% to 50% of the diameter. Definitions and matching rule: docs/LOCALIZATION.md.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "localization/part_symmetries.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::localization {

struct PartDefinition {
  uint32_t part_id = 0;
  std::vector<Eigen::Vector3f> vertices;  // part frame, metres
  PartSymmetries symmetries;              // a part that declares any is scored with ADD-S
  // Above 0: the diameter the thresholds are fractions of (BOP's models_info.json value), taken
  // instead of computing it from the vertices for every call.
  double known_diameter = 0;
};

struct TrueInstance {
  uint32_t part_id = 0;
  Pose3 world_from_part = Pose3::Identity();
  // Share of the instance's surface the scan sees (BOP's visib_fract), in [0, 1].
  double visible_fraction = 1;
};

struct EstimatedInstance {
  uint32_t part_id = 0;
  Pose3 world_from_part = Pose3::Identity();
  double score = 0;  // higher is more confident
};

struct ScoringOptions {
  // True instances seen less than this are left out of recall and of matching (BOP's visib_gt_min).
  double min_visible_fraction = 0.1;
  // ADD(-S) is correct below this fraction of the diameter.
  double add_threshold = 0.1;
  // MSSD thresholds as fractions of the diameter; empty: BOP's 0.05, 0.10, ..., 0.50.
  std::vector<double> mssd_thresholds;
  // Only the best-scored estimates of a part are matched, as many as it has valid true instances
  // (BOP's n_top = -1 of the ViVo task); false: all of them.
  bool keep_top_estimates = true;
  double symmetry_step = kBopSymmetryStep;
  // Polled between pairs of instances; once set, ScoreScan ends with CANCELLED.
  const std::atomic<bool>* cancel = nullptr;
};

// Per valid true instance: the estimate ADD(-S) matched it to, or none, and the errors of that pair.
struct InstanceResult {
  size_t true_index = 0;                  // into the true instances given
  std::optional<size_t> estimate_index;   // into the estimates given
  double add_error = 0;                   // ADD or ADD-S as the part is scored, metres; 0 when unmatched
  double mssd_error = 0;                  // of the same pair
};

struct PartScore {
  uint32_t part_id = 0;
  double diameter = 0;
  bool uses_add_s = false;  // ADD-S (the part declares symmetries) rather than ADD
  size_t valid_instances = 0;
  size_t estimates = 0;
  size_t add_correct = 0;
  // Empty when the part has no valid true instance.
  std::optional<double> add_recall;
  std::optional<double> mssd_average_recall;
  std::vector<double> mssd_recalls;  // per threshold, empty when there is no valid instance
  std::vector<InstanceResult> instances;
};

struct ScanScore {
  std::vector<PartScore> parts;  // in the order of the part definitions
  size_t valid_instances = 0;
  // Over all valid true instances of all parts together, as BOP pools them.
  std::optional<double> add_recall;
  std::optional<double> mssd_average_recall;
};

// InvalidArgument (naming "truth[i].part_id", "estimates[i].score", ...) for unknown parts,
// non-finite values, a part without vertices or a duplicated part id; CANCELLED once
// options.cancel is set.
StatusOr<ScanScore> ScoreScan(std::span<const PartDefinition> parts, std::span<const TrueInstance> truth,
                              std::span<const EstimatedInstance> estimates, const ScoringOptions& options = {});

// BOP's MSSD thresholds: 0.05 to 0.5 of the diameter in steps of 0.05, the same doubles as BOP's
// np.arange(0.05, 0.51, 0.05).
std::vector<double> BopMssdThresholds();

}  // namespace vscan::localization
