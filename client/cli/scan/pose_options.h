#pragma once
// The --position, --rpy, --quat and --matrix options of commands that take a pose (objects, the
// sensor pose of an uploaded cloud).

#include <string>

#include <CLI/CLI.hpp>

#include "session/args.h"

namespace vscan::cli {

// what names the pose in the help text ("" for an object's, "Sensor pose: " for a cloud's).
void AddPoseOptions(CLI::App* cmd, PoseArgs& pose, const std::string& what = "");

}  // namespace vscan::cli
