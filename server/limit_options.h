#pragma once
// vscand's bounds as command-line flags (--max-...), read into service::Limits. Every flag here
// is listed with its default in docs/OPERATIONS.md.

#include <cstdint>

#include <CLI/CLI.hpp>

#include "service/context/server_options.h"

namespace vscan {

// Flags given in MiB, converted by ApplyLimitFlags once parsed.
struct LimitFlagsMib {
  uint64_t upload = 0;
  uint64_t robot_bundle = 0;
  uint64_t request_memory = 0;
  uint64_t job = 0;
  uint64_t data = 0;
};

void AddLimitOptions(CLI::App& app, service::Limits& limits, LimitFlagsMib& mib);
void ApplyLimitFlags(const LimitFlagsMib& mib, service::Limits& limits);

}  // namespace vscan
