#pragma once
// One part placed in the prepared scan, refined and checked against it: the verification every
// voted candidate goes through before the search takes or refuses it.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "localization/baseline_localizer.h"
#include "localization/part_model.h"
#include "localization/prepared_scan.h"
#include "localization/scan_grid.h"
#include "localization/scan_view.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::localization {

// A voted pose is within about one bin of the truth; ICP pairs points up to two bins apart.
inline constexpr double kIcpReachInPpfSteps = 2;
// Hypotheses are ordered by score x (1 - this x seen-through share): half seen through is nothing,
// as true instances of shiny parts have a share of their facing points where the scan saw deeper.
inline constexpr double kSeenThroughWeight = 2;

// One part placed somewhere, refined and checked against the scan.
struct Hypothesis {
  size_t part = 0;
  Pose3 pose = Pose3::Identity();
  double score = 0;
  ScanView::Tally view;
  double below_support = 0;  // share of its points inside what the parts stand on
  std::vector<uint32_t> explained;  // prepared scan points it accounts for
  double Quality() const { return score * std::max(0.0, 1 - kSeenThroughWeight * view.SeenThroughShare()); }
};

// Checks candidate poses of one part against the prepared scan (grid: its points by cells of
// kIcpReachInPpfSteps PPF steps).
class Verifier {
 public:
  Verifier(const PartModel& part, const ScanGrid& grid, const PreparedScan& scan, const LocalizerOptions& options);

  // ICP within two PPF steps, then within explained_distance_voxels; the points it explains, its
  // score, its view tally and its share behind the support plane.
  StatusOr<Hypothesis> Verify(const Pose3& voted) const;

 private:
  std::vector<uint32_t> Near(const Pose3& world_from_part, double reach, double min_cos) const;
  StatusOr<Pose3> Refine(const Pose3& start, double reach) const;
  double ExplainedShare(const Pose3& world_from_part, const std::vector<uint32_t>& explained) const;
  double BelowSupport(const Pose3& world_from_part, double depth) const;

  const PartModel& part_;
  const ScanGrid& grid_;
  const PreparedScan& scan_;
  const LocalizerOptions& options_;
  double min_cos_;
};

}  // namespace vscan::localization
