#include "service/picking/estimates_inbox.h"

#include <cstdio>

namespace vscan::service {
namespace {

std::string FormatSeconds(std::chrono::milliseconds duration) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", duration.count() / 1000.0);
  return text;
}

}  // namespace

void EstimatesInbox::Open(const std::string& job_id, AwaitedStep step) {
  std::lock_guard lock(mutex_);
  slots_[job_id] = Slot{std::move(step), false, std::nullopt};
}

StatusOr<std::vector<picking::Estimate>> EstimatesInbox::Wait(const std::string& job_id,
                                                               std::chrono::milliseconds timeout,
                                                               const std::atomic<bool>* cancel,
                                                               std::chrono::milliseconds poll) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::unique_lock lock(mutex_);
  auto slot = slots_.find(job_id);
  if (slot == slots_.end()) return Internal("estimates inbox: job '" + job_id + "' awaits nothing");
  const size_t step = slot->second.awaited.step;
  StatusOr<std::vector<picking::Estimate>> out = Status::Ok();
  while (true) {
    if (slot->second.delivered) {
      out = std::move(*slot->second.delivered);
      break;
    }
    if (cancel && cancel->load()) {
      out = Cancelled("step " + std::to_string(step) + ": stopped while awaiting estimates");
      break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      out = Status(StatusCode::kDeadlineExceeded, "step " + std::to_string(step) + ": no estimates came within " +
                             FormatSeconds(timeout) + " s");
      break;
    }
    arrived_.wait_until(lock, std::min(deadline, now + poll));
  }
  slots_.erase(slot);
  return out;
}

std::optional<AwaitedStep> EstimatesInbox::Awaiting(const std::string& job_id) const {
  std::lock_guard lock(mutex_);
  const auto slot = slots_.find(job_id);
  if (slot == slots_.end()) return std::nullopt;
  return slot->second.awaited;
}

Status EstimatesInbox::Claim(const std::string& job_id, size_t step) {
  std::lock_guard lock(mutex_);
  const auto slot = slots_.find(job_id);
  if (slot == slots_.end()) {
    return FailedPrecondition("step: job '" + job_id + "' awaits no estimates now");
  }
  if (slot->second.awaited.step != step) {
    return FailedPrecondition("step: job '" + job_id + "' awaits the estimates of step " +
                              std::to_string(slot->second.awaited.step) + ", not of step " + std::to_string(step));
  }
  if (slot->second.claimed) {
    return Status(StatusCode::kAlreadyExists, "step: the estimates of step " + std::to_string(step) + " were sent already");
  }
  slot->second.claimed = true;
  return Status::Ok();
}

bool EstimatesInbox::Deliver(const std::string& job_id, size_t step, std::vector<picking::Estimate> estimates) {
  {
    std::lock_guard lock(mutex_);
    const auto slot = slots_.find(job_id);
    if (slot == slots_.end() || slot->second.awaited.step != step) return false;
    slot->second.delivered = std::move(estimates);
  }
  arrived_.notify_all();
  return true;
}

void EstimatesInbox::Release(const std::string& job_id, size_t step) {
  std::lock_guard lock(mutex_);
  const auto slot = slots_.find(job_id);
  if (slot != slots_.end() && slot->second.awaited.step == step) slot->second.claimed = false;
}

}  // namespace vscan::service
