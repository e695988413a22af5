#pragma once
// How vscand's log lines look: text (the usual pattern plus the request id and fields) or json
// (one object per line: time, level, logger, thread, message, request_id, then the fields).

#include <memory>
#include <optional>
#include <string_view>

#include <spdlog/formatter.h>

namespace vscan::observability {

enum class LogFormat { kText, kJson };

// "text" or "json".
std::optional<LogFormat> ParseLogFormat(std::string_view name);

std::unique_ptr<spdlog::formatter> MakeLogFormatter(LogFormat format);

// Installs the format on spdlog's default logger.
void UseLogFormat(LogFormat format);

}  // namespace vscan::observability
