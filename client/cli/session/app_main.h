#pragma once
// What `vscan` and the other vscan client programs share around their commands: the global options,
// the exit-code footer, and parsing then running the chosen command.

#include <functional>

#include <CLI/CLI.hpp>

#include "session/context.h"

namespace vscan::cli {

// Makes run the work of cmd once cmd has been parsed.
inline void OnRun(CLI::App* cmd, Context& ctx, std::function<int()> run) {
  cmd->callback([&ctx, run = std::move(run)] { ctx.action = run; });
}

// --server, --token, the TLS files, --json, --timeout and --quiet, with their environment variables.
void AddGlobalOptions(CLI::App& app, GlobalOptions& global);

// Adds the exit codes and environment to app's help, parses argv and runs the command it chose.
// Returns the process's exit code.
int ParseAndRun(CLI::App& app, Context& ctx, int argc, char** argv);

}  // namespace vscan::cli
