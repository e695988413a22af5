#include "web/web_request.h"

#include <cctype>
#include <charconv>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace vscan::web {
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string Decode(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] == '%' && i + 2 < text.size() && HexValue(text[i + 1]) >= 0 && HexValue(text[i + 2]) >= 0) {
      out += static_cast<char>(HexValue(text[i + 1]) * 16 + HexValue(text[i + 2]));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

std::optional<std::string> WebRequest::Query(std::string_view key) const {
  std::string_view rest = query;
  while (!rest.empty()) {
    const size_t end = rest.find('&');
    const std::string_view pair = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    const size_t equals = pair.find('=');
    if (Decode(pair.substr(0, equals)) != key) continue;
    return equals == std::string_view::npos ? std::string() : Decode(pair.substr(equals + 1));
  }
  return std::nullopt;
}

WebReply TextReply(int status, std::string message) {
  return {status, "text/plain; charset=utf-8", std::move(message) + "\n", {}};
}

WebReply JsonReply(std::string json) { return {200, kJsonType, std::move(json), {}}; }

WebReply FromStatus(const Status& status) {
  switch (status.code()) {
    case StatusCode::kNotFound: return TextReply(404, status.ToString());
    case StatusCode::kInvalidArgument:
    case StatusCode::kOutOfRange: return TextReply(400, status.ToString());
    case StatusCode::kFailedPrecondition: return TextReply(409, status.ToString());
    case StatusCode::kResourceExhausted: return TextReply(422, status.ToString());
    default: break;
  }
  spdlog::warn("web view: {}", status.ToString());
  return TextReply(500, "internal error");
}

bool IsId(std::string_view id) {
  if (id.empty() || id.size() > 128) return false;
  for (const char c : id) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

StatusOr<long long> QueryInteger(const WebRequest& request, std::string_view key, long long fallback, long long min,
                                 long long max) {
  const std::optional<std::string> text = request.Query(key);
  if (!text) return fallback;
  long long value = 0;
  const char* end = text->data() + text->size();
  const auto [at, error] = std::from_chars(text->data(), end, value);
  if (error != std::errc() || at != end || value < min || value > max) {
    return InvalidArgument(fmt::format("{}: '{}' is not an integer from {} to {}", key, *text, min, max));
  }
  return value;
}

}  // namespace vscan::web
