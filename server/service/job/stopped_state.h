#pragma once
// The state a job of any kind ends in when its runner stops it.

#include "jobs/job_runner.h"
#include "store/stored_enums.h"

namespace vscan::service {

// Cancelled when a client asked; interrupted (resumable) when the server shut down.
inline store::JobState StoppedState(jobs::StopReason reason) {
  return reason == jobs::StopReason::kCancelled ? store::JobState::kCancelled : store::JobState::kInterrupted;
}

}  // namespace vscan::service
