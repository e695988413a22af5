#pragma once
// `vscan bin scan JOB -o OUT.ply`: a scan of a filled bin from above it, with a sensor preset, the
// cloud written with instance ids and OUT.gt.json beside it (each part's true pose and visible
// fraction).

#include <CLI/CLI.hpp>

#include "session/context.h"

namespace vscan::cli {

void AddBinScan(CLI::App& group, Context& ctx);

}  // namespace vscan::cli
