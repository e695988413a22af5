#include "grasping/gripper.h"

#include <cmath>
#include <string>

namespace vscan::grasping {
namespace {

constexpr double kMaxLengthM = 2.0;

Status CheckLength(double value, const char* field) {
  if (!std::isfinite(value) || value <= 0 || value > kMaxLengthM) {
    return InvalidArgument(field, "must be a length in (0, 2] m");
  }
  return Status::Ok();
}

Status CheckAngle(double value, const char* field) {
  if (!std::isfinite(value) || value <= 0 || value >= 90) return InvalidArgument(field, "must be in (0, 90) degrees");
  return Status::Ok();
}

Status Validate(const SuctionCup& cup) {
  if (auto s = CheckLength(cup.diameter_m, "gripper.suction.diameter_m"); !s.ok()) return s;
  if (auto s = CheckLength(cup.stroke_m, "gripper.suction.stroke_m"); !s.ok()) return s;
  if (auto s = CheckAngle(cup.max_tilt_deg, "gripper.suction.max_tilt_deg"); !s.ok()) return s;
  if (!std::isfinite(cup.min_flat_fraction) || cup.min_flat_fraction <= 0 || cup.min_flat_fraction > 1) {
    return InvalidArgument("gripper.suction.min_flat_fraction", "must be in (0, 1]");
  }
  return Status::Ok();
}

Status Validate(const ParallelJaws& jaws) {
  if (auto s = CheckLength(jaws.min_opening_m, "gripper.jaws.min_opening_m"); !s.ok()) return s;
  if (auto s = CheckLength(jaws.max_opening_m, "gripper.jaws.max_opening_m"); !s.ok()) return s;
  if (jaws.min_opening_m > jaws.max_opening_m) {
    return InvalidArgument("gripper.jaws.max_opening_m", "must be >= gripper.jaws.min_opening_m");
  }
  if (auto s = CheckLength(jaws.finger_width_m, "gripper.jaws.finger_width_m"); !s.ok()) return s;
  if (auto s = CheckLength(jaws.finger_depth_m, "gripper.jaws.finger_depth_m"); !s.ok()) return s;
  if (auto s = CheckLength(jaws.finger_length_m, "gripper.jaws.finger_length_m"); !s.ok()) return s;
  if (auto s = CheckLength(jaws.finger_thickness_m, "gripper.jaws.finger_thickness_m"); !s.ok()) return s;
  return CheckAngle(jaws.max_friction_angle_deg, "gripper.jaws.max_friction_angle_deg");
}

}  // namespace

Status ValidateGripper(const Gripper& gripper) {
  return std::visit([](const auto& g) { return Validate(g); }, gripper);
}

}  // namespace vscan::grasping
