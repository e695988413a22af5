#include "service/bins/bin_fill_progress.h"

#include <algorithm>
#include <cmath>

namespace vscan::service {

ProgressFillWorld::ProgressFillWorld(std::unique_ptr<physics::FillWorld> world, double time_step_s,
                                     double slow_linear_m_per_s, double slow_angular_rad_per_s, Observer observer)
    : ForwardingFillWorld(std::move(world)), time_step_s_(time_step_s), slow_linear_(slow_linear_m_per_s),
      slow_angular_(slow_angular_rad_per_s), observer_(std::move(observer)),
      steps_per_report_(std::max<uint64_t>(1, static_cast<uint64_t>(std::llround(1.0 / time_step_s)))) {}

size_t ProgressFillWorld::AddPart(size_t type, const Pose3& world_from_body) {
  const size_t body = inner().AddPart(type, world_from_body);
  live_.insert(body);
  ++dropped_;
  return body;
}

void ProgressFillWorld::RemovePart(size_t body) {
  inner().RemovePart(body);
  live_.erase(body);
}

void ProgressFillWorld::Step() {
  inner().Step();
  if (++steps_ % steps_per_report_ == 0 && observer_) observer_(Progress());
}

FillProgress ProgressFillWorld::Progress() const {
  FillProgress progress;
  progress.simulated_s = static_cast<double>(steps_) * time_step_s_;
  progress.dropped = dropped_;
  progress.removed = dropped_ - live_.size();
  for (size_t body : live_) {
    const physics::BodyState state = inner().State(body);
    if (state.linear_speed < slow_linear_ && state.angular_speed < slow_angular_) ++progress.slow;
  }
  return progress;
}

}  // namespace vscan::service
