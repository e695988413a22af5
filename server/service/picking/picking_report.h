#pragma once
// What a picking job did, for picking.json (the job's ReportWriter prints it as
// proto/vscan/v1/reports.proto's PickingReport), and each step's truth file.

#include <optional>
#include <string>
#include <vector>

#include "picking/empty_bin.h"
#include "service/picking/picking_session.h"
#include "store/job_catalogue.h"

namespace vscan::service {

struct PickingJobReport {
  std::string job_id;
  std::string name;
  std::string bin_job_id;
  store::JobState state = store::JobState::kSucceeded;
  std::string message;
  size_t parts_at_start = 0;
  // Unset when the run failed before it ended by itself.
  std::optional<picking::EmptyBinResult> result;
  // Per step, the names of its artifacts (empty when not written).
  std::vector<std::string> scan_artifacts;
  std::vector<std::string> truth_artifacts;
};

const char* PerceptionName(Perception perception);

}  // namespace vscan::service
