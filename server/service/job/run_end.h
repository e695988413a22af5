#pragma once
// How a job of any kind ends when its runner stops it, and how every run records its end.

#include <string>

#include <spdlog/spdlog.h>

#include "jobs/job_runner.h"
#include "service/job/job_events.h"
#include "store/stored_enums.h"

namespace vscan::service {

// Cancelled when a client asked; interrupted (resumable) when the server shut down.
inline store::JobState StoppedState(jobs::StopReason reason) {
  return reason == jobs::StopReason::kCancelled ? store::JobState::kCancelled : store::JobState::kInterrupted;
}

// How a stopped job's message begins.
inline std::string StoppedMessage(store::JobState state) {
  return state == store::JobState::kCancelled ? "cancelled" : "server stopped while the job ran";
}

// An event of a run: its message, the steps done, and its state (running unless it is the end).
inline JobEventUpdate RunUpdate(const std::string& message, uint32_t steps_done,
                                store::JobState state = store::JobState::kRunning) {
  JobEventUpdate update;
  update.state = state;
  update.message = message;
  update.steps_done = steps_done;
  return update;
}

// Stores a JSON report the run leaves however it ends; one that cannot be stored is logged, and
// the run still ends.
inline void RecordReport(JobRecorder& recorder, const std::string& job_id, const std::string& name,
                         const std::string& json, uint32_t steps_done) {
  const auto stored =
      recorder.RecordArtifact(name, "application/json", json, nullptr, nullptr, RunUpdate(name + " written", steps_done));
  if (!stored.ok()) spdlog::warn("job {}: {} not stored: {}", job_id, name, stored.status().ToString());
}

// The final event of a run. Nothing is left for the run to do when it cannot be stored, so that
// is logged, not returned; the catalogue marks the job interrupted at the next start.
inline void RecordEnd(JobRecorder& recorder, const std::string& job_id, const JobEventUpdate& final_update) {
  const Status ended = recorder.End(final_update);
  if (!ended.ok()) spdlog::error("job {}: cannot record its end: {}", job_id, ended.ToString());
  spdlog::info("job {} {}: {}", job_id, store::JobStateName(final_update.state), final_update.message);
}

}  // namespace vscan::service
