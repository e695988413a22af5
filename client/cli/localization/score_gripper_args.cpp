#include "localization/score_gripper_args.h"

#include <string>

namespace vscan::cli {

void AddScoreGripperOptions(CLI::App* command, ScoreGripperArgs& a) {
  const char* group = "Grasp success (a gripper's grasp planned on each estimate, tried on the truth)";
  command->add_option("--suction-diameter", a.suction_diameter, "Suction cup: diameter, m (0.02)")->group(group);
  command->add_option("--stroke", a.stroke, "Suction cup: how far the bellows compress, m (0.01)")->group(group);
  command->add_option("--max-tilt", a.max_tilt_deg, "Suction cup: surface tilt off its axis, degrees (10)")->group(group);
  command->add_option("--min-flat", a.min_flat_fraction, "Suction cup: share of its disc on the part (0.9)")->group(group);
  command->add_option("--jaws-max-opening", a.jaws_max_opening, "Jaws: widest opening, m (0.05)")->group(group);
  command->add_option("--jaws-min-opening", a.jaws_min_opening, "Jaws: narrowest grip, m (0.005)")->group(group);
  command->add_option("--finger-width", a.finger_width, "Jaws: pad width across the approach, m (0.01)")->group(group);
  command->add_option("--finger-depth", a.finger_depth, "Jaws: pad depth along the approach, m (0.01)")->group(group);
  command->add_option("--up", a.up, "X Y Z: against gravity in the poses' frame (0 0 1)")->expected(3)->group(group);
}

StatusOr<std::optional<v1::Gripper>> BuildScoreGripper(const ScoreGripperArgs& a) {
  const bool cup = a.suction_diameter || a.stroke || a.max_tilt_deg || a.min_flat_fraction;
  const bool jaws = a.jaws_max_opening || a.jaws_min_opening || a.finger_width || a.finger_depth;
  if (cup && jaws) {
    return InvalidArgument("--suction-diameter", "a suction cup's flags and the jaws' flags given together; give one gripper");
  }
  if (!cup && !jaws) return std::optional<v1::Gripper>();
  v1::Gripper gripper;
  if (cup) {
    v1::SuctionCup* out = gripper.mutable_suction();
    if (a.suction_diameter) out->set_diameter(*a.suction_diameter);
    if (a.stroke) out->set_stroke(*a.stroke);
    if (a.max_tilt_deg) out->set_max_tilt_deg(*a.max_tilt_deg);
    if (a.min_flat_fraction) out->set_min_flat_fraction(*a.min_flat_fraction);
  } else {
    v1::ParallelJaws* out = gripper.mutable_jaws();
    if (a.jaws_max_opening) out->set_max_opening(*a.jaws_max_opening);
    if (a.jaws_min_opening) out->set_min_opening(*a.jaws_min_opening);
    if (a.finger_width) out->set_finger_width(*a.finger_width);
    if (a.finger_depth) out->set_finger_depth(*a.finger_depth);
  }
  return std::optional<v1::Gripper>(gripper);
}

std::optional<v1::Vector3> ScoreUp(const ScoreGripperArgs& a) {
  if (a.up.size() != 3) return std::nullopt;
  v1::Vector3 up;
  up.set_x(a.up[0]);
  up.set_y(a.up[1]);
  up.set_z(a.up[2]);
  return up;
}

}  // namespace vscan::cli
