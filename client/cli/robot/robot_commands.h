#pragma once
// The subcommands of `vscan robot`, split by concern.

#include <CLI/CLI.hpp>

#include "session/context.h"

namespace vscan::cli {

// fk, ik.
void AddRobotKinematicsCommands(CLI::App& group, Context& ctx);
// mount, unmount, mounts.
void AddRobotMountCommands(CLI::App& group, Context& ctx);

}  // namespace vscan::cli
