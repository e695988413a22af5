#include "picking/gripper_args.h"

#include <string>
#include <utility>
#include <vector>

namespace vscan::cli {
namespace {

using Flag = std::pair<const char*, const std::optional<double>*>;

std::vector<Flag> SuctionFlags(const GripperArgs& a) {
  return {{"--suction-diameter", &a.suction_diameter},
          {"--stroke", &a.stroke},
          {"--max-tilt", &a.max_tilt_deg},
          {"--min-flat", &a.min_flat_fraction}};
}

std::vector<Flag> JawFlags(const GripperArgs& a) {
  return {{"--jaws-max-opening", &a.jaws_max_opening}, {"--jaws-min-opening", &a.jaws_min_opening},
          {"--finger-width", &a.finger_width},         {"--finger-depth", &a.finger_depth},
          {"--finger-length", &a.finger_length},       {"--finger-thickness", &a.finger_thickness},
          {"--friction-deg", &a.friction_deg}};
}

const char* FirstGiven(const std::vector<Flag>& flags) {
  for (const auto& [name, value] : flags) {
    if (value->has_value()) return name;
  }
  return nullptr;
}

}  // namespace

void AddGripperOptions(CLI::App* command, GripperArgs& a) {
  const char* cup = "Suction cup";
  command->add_option("--suction-diameter", a.suction_diameter, "Suction cup: diameter, m (0.02)")->group(cup);
  command->add_option("--stroke", a.stroke, "Suction cup: how far the bellows compress, m (0.01)")->group(cup);
  command->add_option("--max-tilt", a.max_tilt_deg, "Suction cup: surface tilt off the cup's axis, degrees (10)")
      ->group(cup);
  command->add_option("--min-flat", a.min_flat_fraction, "Suction cup: share of the disc on the part, (0, 1] (0.9)")
      ->group(cup);
  const char* jaws = "Parallel jaws";
  command->add_option("--jaws-max-opening", a.jaws_max_opening, "Jaws: widest opening, m (0.05)")->group(jaws);
  command->add_option("--jaws-min-opening", a.jaws_min_opening, "Jaws: narrowest grip, m (0.005)")->group(jaws);
  command->add_option("--finger-width", a.finger_width, "Jaws: pad width across the approach, m (0.01)")->group(jaws);
  command->add_option("--finger-depth", a.finger_depth, "Jaws: pad depth along the approach, m (0.01)")->group(jaws);
  command->add_option("--finger-length", a.finger_length, "Jaws: finger from the pad back to the palm, m (0.04)")
      ->group(jaws);
  command->add_option("--finger-thickness", a.finger_thickness, "Jaws: finger thickness, m (0.005)")->group(jaws);
  command->add_option("--friction-deg", a.friction_deg, "Jaws: friction cone half-angle, degrees (15)")->group(jaws);
}

StatusOr<v1::Gripper> BuildGripper(const GripperArgs& a) {
  const char* cup_flag = FirstGiven(SuctionFlags(a));
  const char* jaw_flag = FirstGiven(JawFlags(a));
  v1::Gripper gripper;
  if (cup_flag && jaw_flag) {
    return InvalidArgument(std::string(cup_flag), std::string("a suction cup's flag, given with the jaws' ") + jaw_flag +
                                                      "; give one gripper");
  }
  if (cup_flag) {
    v1::SuctionCup* cup = gripper.mutable_suction();
    if (a.suction_diameter) cup->set_diameter(*a.suction_diameter);
    if (a.stroke) cup->set_stroke(*a.stroke);
    if (a.max_tilt_deg) cup->set_max_tilt_deg(*a.max_tilt_deg);
    if (a.min_flat_fraction) cup->set_min_flat_fraction(*a.min_flat_fraction);
  } else if (jaw_flag) {
    v1::ParallelJaws* jaws = gripper.mutable_jaws();
    if (a.jaws_max_opening) jaws->set_max_opening(*a.jaws_max_opening);
    if (a.jaws_min_opening) jaws->set_min_opening(*a.jaws_min_opening);
    if (a.finger_width) jaws->set_finger_width(*a.finger_width);
    if (a.finger_depth) jaws->set_finger_depth(*a.finger_depth);
    if (a.finger_length) jaws->set_finger_length(*a.finger_length);
    if (a.finger_thickness) jaws->set_finger_thickness(*a.finger_thickness);
    if (a.friction_deg) jaws->set_max_friction_angle_deg(*a.friction_deg);
  }
  return gripper;
}

}  // namespace vscan::cli
