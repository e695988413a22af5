#pragma once
// bin.json: what a bin fill did, written however it ends: the bin, each part's type, mesh, object
// and settled pose, the parts that left the bin, the end reason, the physics' counters and times.
// The job's ReportWriter prints it as proto/vscan/v1/reports.proto's BinReport.

#include <optional>
#include <string>

#include "physics/bin_fill.h"
#include "service/bins/bin_fill_plan.h"
#include "service/bins/bin_scene.h"
#include "service/bins/bin_picks.h"
#include "store/job_catalogue.h"

namespace vscan::service {

struct BinFillReport {
  std::string job_id;
  store::JobState state = store::JobState::kSucceeded;
  std::string message;
  // Unset when the fill never ran to an end (a failure before or during it).
  std::optional<physics::FillResult> result;
  // Set when the settled parts became objects of the scene.
  std::optional<BinPlacement> placement;
  // Set when the plan asked for picks and the check ran over the placed parts (parts[i] is the
  // verdict of placement->parts[i]).
  std::optional<BinPicks> picks;
};

// "m", "mm", "in", ... as the plan files name units.
const char* UnitName(store::LengthUnit unit);

}  // namespace vscan::service
