#pragma once
// The gripper of `vscan score` and `vscan dataset score`: the flags of `vscan picks`
// (picking/gripper_args.h) and --up, for the grasp success beside the recalls.

#include <optional>
#include <vector>

#include <CLI/CLI.hpp>

#include "picking/gripper_args.h"
#include "vscan/common/status.h"
#include "vscan/v1/common.pb.h"
#include "vscan/v1/picking.pb.h"

namespace vscan::cli {

struct ScoreGripperArgs {
  GripperArgs gripper;
  std::vector<double> up;  // empty or x y z
};

void AddScoreGripperOptions(CLI::App* command, ScoreGripperArgs& args);

// Unset when no gripper flag is given; INVALID_ARGUMENT naming a flag when a cup's and the jaws'
// flags are mixed.
StatusOr<std::optional<v1::Gripper>> BuildScoreGripper(const ScoreGripperArgs& args);

// --up as a message, or unset.
std::optional<v1::Vector3> ScoreUp(const ScoreGripperArgs& args);

}  // namespace vscan::cli
