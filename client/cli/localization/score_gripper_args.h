#pragma once
// The gripper flags of `vscan score` and `vscan dataset score` (the same names as `vscan picks`):
// a suction cup or parallel jaws whose grasps, planned on each estimate, are tried on the truth.

#include <optional>
#include <vector>

#include <CLI/CLI.hpp>

#include "vscan/common/status.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::cli {

// Metres and degrees; unset flags are not sent (the server's defaults, docs/GRASPING.md).
struct ScoreGripperArgs {
  std::optional<double> suction_diameter, stroke, max_tilt_deg, min_flat_fraction;
  std::optional<double> jaws_max_opening, jaws_min_opening, finger_width, finger_depth;
  std::vector<double> up;  // empty or x y z
};

void AddScoreGripperOptions(CLI::App* command, ScoreGripperArgs& args);

// Unset when no gripper flag is given; INVALID_ARGUMENT naming a flag when a cup's and the jaws'
// flags are mixed.
StatusOr<std::optional<v1::Gripper>> BuildScoreGripper(const ScoreGripperArgs& args);

// --up as a message, or unset.
std::optional<v1::Vector3> ScoreUp(const ScoreGripperArgs& args);

}  // namespace vscan::cli
