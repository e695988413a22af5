#pragma once
// The outcome of vscan-load as text or one JSON object.

#include <optional>
#include <string>

#include <sys/types.h>

#include "load_runner.h"
#include "memory_sampler.h"

namespace vscan::cli {

struct LoadReport {
  LoadLimits limits;
  uint32_t width = 0;
  uint32_t height = 0;
  LoadRun run;
  // The server process and its memory while the load ran, when it could be found and read.
  std::optional<pid_t> server_pid;
  std::optional<MemorySummary> memory;
};

std::string FormatLoadReportText(const LoadReport& report);
std::string FormatLoadReportJson(const LoadReport& report);

}  // namespace vscan::cli
