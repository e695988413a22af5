#include "api/transport/validate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace vscan::api {
namespace {

constexpr int kDefaultPageSize = 100;
constexpr size_t kIdHexDigits = 16;

}  // namespace

Status RequireId(const std::string& id, std::string_view field) {
  if (id.empty()) return InvalidArgument(std::string(field), "required");
  if (id.size() > 64) return InvalidArgument(std::string(field), "longer than 64 characters");
  // Ids are a prefix and hex digits; anything else (NUL, '/', '.', non-ASCII) cannot name a record.
  const auto bad = std::find_if(id.begin(), id.end(), [](unsigned char c) {
    return c >= 0x80 || !(std::isalnum(c) || c == '_' || c == '-');
  });
  if (bad != id.end()) {
    return InvalidArgument(std::string(field), "may hold only ASCII letters, digits, '_' and '-' (byte " +
                                                   std::to_string(bad - id.begin()) + " is not one)");
  }
  return Status::Ok();
}

Status CheckText(const std::string& text, std::string_view field, size_t max_length) {
  if (text.size() > max_length) {
    return InvalidArgument(std::string(field), "longer than " + std::to_string(max_length) + " bytes");
  }
  const auto control = std::find_if(text.begin(), text.end(), [](unsigned char c) { return c < 0x20 || c == 0x7f; });
  if (control != text.end()) {
    return InvalidArgument(std::string(field) + ": control character (code " +
                           std::to_string(static_cast<unsigned char>(*control)) + ") at byte " +
                           std::to_string(control - text.begin()));
  }
  return Status::Ok();
}

Status CheckPageToken(const std::string& token, std::string_view id_prefix) {
  if (token.empty()) return Status::Ok();
  const bool well_formed = token.size() == id_prefix.size() + kIdHexDigits && token.starts_with(id_prefix) &&
                           std::all_of(token.begin() + id_prefix.size(), token.end(), [](char c) {
                             return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
                           });
  if (!well_formed) {
    return InvalidArgument("page_token: not a token this call returned (expected empty or '" +
                           std::string(id_prefix) + "' and 16 hex digits)");
  }
  return Status::Ok();
}

StatusOr<double> ScaleOrDefault(double scale, std::string_view field) {
  if (scale == 0.0) return 1.0;
  if (!std::isfinite(scale) || scale < 0 || scale > 1e6) {
    return InvalidArgument(std::string(field), "must be a finite number in (0, 1e6]");
  }
  return scale;
}

StatusOr<double> NumberOrDefault(double value, double fallback, double lo, double hi, const std::string& field,
                                 const char* unit) {
  if (value == 0) return fallback;
  if (!std::isfinite(value) || value < lo || value > hi) {
    const auto number = [](double x) {
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%g", x);
      return std::string(buffer);
    };
    return InvalidArgument(field, "must be finite and within [" + number(lo) + ", " + number(hi) + "] " + unit +
                                      " (0: " + number(fallback) + "), got " + number(value));
  }
  return value;
}

StatusOr<int> PageSize(int32_t page_size, uint32_t max_page_size) {
  if (page_size < 0) return InvalidArgument("page_size", "must not be negative");
  if (page_size == 0) return std::min<int>(kDefaultPageSize, static_cast<int>(max_page_size));
  return std::min<int>(page_size, static_cast<int>(max_page_size));
}

}  // namespace vscan::api
