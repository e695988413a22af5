#pragma once
// Where picking jobs with client perception wait for a step's estimates and where
// SubmitPickingEstimates hands them over. In memory; the caller stores them durably between
// Claim and Deliver. No lock is held while a job waits.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "picking/empty_bin.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::service {

// What a job waits for: its step, the scan a client localizes and the names an estimate may use.
struct AwaitedStep {
  size_t step = 0;
  std::string scan_artifact;
  Pose3 world_from_sensor = Pose3::Identity();
  std::vector<std::string> part_names;
  std::vector<std::pair<size_t, size_t>> pile;  // (type, instance) of the parts the scan saw
  std::vector<size_t> grasps_per_type;           // what an estimate of each type costs the plan
};

class EstimatesInbox {
 public:
  // The job's thread: from now on Awaiting(job_id) shows step.
  void Open(const std::string& job_id, AwaitedStep step);
  // The job's thread, after Open: the delivered estimates; CANCELLED once *cancel is set (checked
  // every poll); DEADLINE_EXCEEDED when none came within timeout. The job no longer awaits after.
  StatusOr<std::vector<picking::Estimate>> Wait(const std::string& job_id, std::chrono::milliseconds timeout,
                                                const std::atomic<bool>* cancel,
                                                std::chrono::milliseconds poll = std::chrono::milliseconds(50));
  std::optional<AwaitedStep> Awaiting(const std::string& job_id) const;
  // The sender: reserves the step. FAILED_PRECONDITION when the job awaits nothing or another
  // step (naming it); ALREADY_EXISTS when the step was claimed already.
  Status Claim(const std::string& job_id, size_t step);
  // Hands over a claimed step's estimates (or gives the claim back). False when the job stopped
  // waiting meanwhile.
  bool Deliver(const std::string& job_id, size_t step, std::vector<picking::Estimate> estimates);
  void Release(const std::string& job_id, size_t step);

 private:
  struct Slot {
    AwaitedStep awaited;
    bool claimed = false;
    std::optional<std::vector<picking::Estimate>> delivered;
  };
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::string, Slot> slots_;
};

}  // namespace vscan::service
