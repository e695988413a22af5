#pragma once
// One place that configures spdlog for every vscan program.

#include <string_view>

namespace vscan {

// level: trace, debug, info, warn, error, off. Logs go to stderr.
void SetupLogging(std::string_view program, std::string_view level);

}  // namespace vscan
