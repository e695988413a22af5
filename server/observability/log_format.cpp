#include "observability/log_format.h"

#include <chrono>
#include <string>

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <spdlog/pattern_formatter.h>
#include <spdlog/spdlog.h>

#include "observability/log_fields.h"
#include "observability/request_id.h"

namespace vscan::observability {
namespace {

void AppendJsonString(spdlog::memory_buf_t& out, std::string_view text) {
  out.push_back('"');
  for (const char c : text) {
    switch (c) {
      case '"': out.append(std::string_view("\\\"")); break;
      case '\\': out.append(std::string_view("\\\\")); break;
      case '\n': out.append(std::string_view("\\n")); break;
      case '\r': out.append(std::string_view("\\r")); break;
      case '\t': out.append(std::string_view("\\t")); break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          fmt::format_to(std::back_inserter(out), "\\u{:04x}", static_cast<int>(c));
        } else {
          out.push_back(c);
        }
    }
  }
  out.push_back('"');
}

void AppendKey(spdlog::memory_buf_t& out, std::string_view key) {
  out.push_back(',');
  AppendJsonString(out, key);
  out.push_back(':');
}

class JsonFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& out) override {
    const auto since_epoch = msg.time.time_since_epoch();
    const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch);
    const auto millis = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds).count();
    fmt::format_to(std::back_inserter(out), "{{\"time\":\"{:%Y-%m-%dT%H:%M:%S}.{:03d}Z\"",
                   fmt::gmtime(static_cast<std::time_t>(seconds.count())), millis);
    AppendKey(out, "level");
    const auto level = spdlog::level::to_string_view(msg.level);
    AppendJsonString(out, std::string_view(level.data(), level.size()));
    AppendKey(out, "logger");
    AppendJsonString(out, std::string_view(msg.logger_name.data(), msg.logger_name.size()));
    AppendKey(out, "thread");
    fmt::format_to(std::back_inserter(out), "{}", msg.thread_id);
    AppendKey(out, "message");
    AppendJsonString(out, std::string_view(msg.payload.data(), msg.payload.size()));
    if (const std::string& id = CurrentRequestId(); !id.empty()) {
      AppendKey(out, "request_id");
      AppendJsonString(out, id);
    }
    for (const LogField& field : CurrentLogFields()) {
      AppendKey(out, field.key);
      if (field.number) {
        out.append(field.value);
      } else {
        AppendJsonString(out, field.value);
      }
    }
    out.push_back('}');
    out.append(std::string_view(spdlog::details::os::default_eol));
  }

  std::unique_ptr<spdlog::formatter> clone() const override { return std::make_unique<JsonFormatter>(); }
};

// %* in a text pattern: " [req <id>]" while the thread works for a call, else nothing.
class RequestFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg&, const std::tm&, spdlog::memory_buf_t& out) override {
    if (const std::string& id = CurrentRequestId(); !id.empty()) {
      out.append(std::string_view(" [req "));
      out.append(id);
      out.push_back(']');
    }
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<RequestFlag>(); }
};

// %& in a text pattern: " key=value" for each field the thread has set.
class FieldsFlag final : public spdlog::custom_flag_formatter {
 public:
  void format(const spdlog::details::log_msg&, const std::tm&, spdlog::memory_buf_t& out) override {
    for (const LogField& field : CurrentLogFields()) {
      out.push_back(' ');
      out.append(field.key);
      out.push_back('=');
      out.append(field.value);
    }
  }
  std::unique_ptr<custom_flag_formatter> clone() const override { return std::make_unique<FieldsFlag>(); }
};

}  // namespace

std::optional<LogFormat> ParseLogFormat(std::string_view name) {
  if (name == "text") return LogFormat::kText;
  if (name == "json") return LogFormat::kJson;
  return std::nullopt;
}

std::unique_ptr<spdlog::formatter> MakeLogFormatter(LogFormat format) {
  if (format == LogFormat::kJson) return std::make_unique<JsonFormatter>();
  auto formatter = std::make_unique<spdlog::pattern_formatter>();
  formatter->add_flag<RequestFlag>('*').add_flag<FieldsFlag>('&');
  formatter->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ [%n]%* %v%&");
  return formatter;
}

void UseLogFormat(LogFormat format) { spdlog::default_logger()->set_formatter(MakeLogFormatter(format)); }

}  // namespace vscan::observability
