#pragma once
// A FillWorld that passes every call to the physics world it wraps and, once per simulated
// second, tells its observer how far the fill has come: parts dropped, resting and removed.

#include <cstdint>
#include <functional>
#include <memory>
#include <set>

#include "physics/fill_world.h"

namespace vscan::service {

struct FillProgress {
  double simulated_s = 0;
  uint64_t dropped = 0;  // parts added so far
  uint64_t removed = 0;  // parts that left the bin
  uint64_t slow = 0;     // parts in the bin now moving slower than the speeds at which Bullet lets them sleep
};

class ProgressFillWorld final : public physics::ForwardingFillWorld {
 public:
  using Observer = std::function<void(const FillProgress&)>;
  ProgressFillWorld(std::unique_ptr<physics::FillWorld> world, double time_step_s, double slow_linear_m_per_s,
                    double slow_angular_rad_per_s, Observer observer);

  size_t AddPart(size_t type, const Pose3& world_from_body) override;
  void RemovePart(size_t body) override;
  void Step() override;

  FillProgress Progress() const;

 private:
  double time_step_s_;
  double slow_linear_;
  double slow_angular_;
  Observer observer_;
  uint64_t steps_ = 0;
  uint64_t steps_per_report_;
  uint64_t dropped_ = 0;
  std::set<size_t> live_;
};

}  // namespace vscan::service
