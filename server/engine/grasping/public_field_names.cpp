#include "grasping/public_field_names.h"

#include <utility>

namespace vscan::grasping {
namespace {

constexpr std::pair<std::string_view, std::string_view> kPublicNames[] = {
    {"gripper.suction.diameter_m", "gripper.suction.diameter"},
    {"gripper.suction.stroke_m", "gripper.suction.stroke"},
    {"gripper.jaws.min_opening_m", "gripper.jaws.min_opening"},
    {"gripper.jaws.max_opening_m", "gripper.jaws.max_opening"},
    {"gripper.jaws.finger_width_m", "gripper.jaws.finger_width"},
    {"gripper.jaws.finger_depth_m", "gripper.jaws.finger_depth"},
    {"gripper.jaws.finger_length_m", "gripper.jaws.finger_length"},
    {"gripper.jaws.finger_thickness_m", "gripper.jaws.finger_thickness"},
    {"pick_options.approach_m", "pick_options.approach_distance"},
    {"pick_options.cover_distance_m", "pick_options.cover_distance"},
    {"pick_options.body_length_m", "pick_options.body_length"},
};

}  // namespace

std::string_view PublicFieldName(std::string_view engine_field) {
  for (const auto& [engine, public_name] : kPublicNames) {
    if (engine_field == engine) return public_name;
  }
  return engine_field;
}

}  // namespace vscan::grasping
