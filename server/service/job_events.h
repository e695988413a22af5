#pragma once
// What a running job reports, and to whom: every change is recorded durably before anyone sees it.

#include <cstdint>
#include <string>

#include "store/cloud_catalogue.h"
#include "store/job_catalogue.h"
#include "vscan/common/status.h"

namespace vscan::service {

struct CampaignStepRecord;

// What one event changes.
struct JobEventUpdate {
  store::JobState state = store::JobState::kRunning;
  std::string message;
  uint32_t steps_done = 0;
  uint32_t step = 0;
  bool pose_reached = false;
};

// Where a job's events and artifacts go (the job tracker, in vscand).
class JobRecorder {
 public:
  virtual ~JobRecorder() = default;
  virtual Status Record(const JobEventUpdate& update) = 0;
  // Stores bytes durably and records them with the event; scan, when given, describes the scan
  // the bytes hold, and cloud the stored cloud they also are (its origin, job, blob and size are
  // filled in). Returns the artifact's id.
  virtual StatusOr<std::string> RecordArtifact(const std::string& name, const std::string& media_type,
                                               const std::string& bytes, const CampaignStepRecord* scan,
                                               const store::CloudRecord* cloud, const JobEventUpdate& update) = 0;
  // The final event: update.state must be final.
  virtual Status End(const JobEventUpdate& update) = 0;
};

}  // namespace vscan::service
