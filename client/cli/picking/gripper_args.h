#pragma once
// The gripper flags `vscan grasps` and `vscan picks` share: a suction cup or parallel jaws, sent to
// the server as given (the server validates each value and names its field).

#include <optional>

#include <CLI/CLI.hpp>

#include "vscan/common/status.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::cli {

// Unset flags are not sent (the server's defaults, docs/GRASPING.md). Metres and degrees.
struct GripperArgs {
  std::optional<double> suction_diameter;
  std::optional<double> stroke;
  std::optional<double> max_tilt_deg;
  std::optional<double> min_flat_fraction;
  std::optional<double> jaws_max_opening;
  std::optional<double> jaws_min_opening;
  std::optional<double> finger_width;
  std::optional<double> finger_depth;
  std::optional<double> finger_length;
  std::optional<double> finger_thickness;
  std::optional<double> friction_deg;
};

void AddGripperOptions(CLI::App* command, GripperArgs& args);

// A suction cup when any cup flag is given, jaws when any jaw flag is; INVALID_ARGUMENT naming the
// flags when both kinds are mixed. Neither: an empty Gripper, which the server refuses.
StatusOr<v1::Gripper> BuildGripper(const GripperArgs& args);

}  // namespace vscan::cli
