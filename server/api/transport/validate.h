#pragma once
// Small checks of request fields; every message names the field.

#include <cstdint>
#include <string>
#include <string_view>

#include "vscan/common/status.h"

namespace vscan::api {

// Present, at most 64 bytes, of ASCII letters, digits, '_' and '-' only (INVALID_ARGUMENT otherwise).
Status RequireId(const std::string& id, std::string_view field);
// At most max_length bytes and no control characters (NUL, newline, ...).
Status CheckText(const std::string& text, std::string_view field, size_t max_length = 256);
// Empty, or an id of the listed kind (id_prefix + 16 hex digits) as a previous page returned.
Status CheckPageToken(const std::string& token, std::string_view id_prefix);
// 0 means 1; otherwise finite, positive and at most 1e6.
StatusOr<double> ScaleOrDefault(double scale, std::string_view field);
// 0 takes fallback; otherwise finite and within [lo, hi] in `unit` (INVALID_ARGUMENT naming field).
StatusOr<double> NumberOrDefault(double value, double fallback, double lo, double hi, const std::string& field,
                                 const char* unit);
// page_size 0 means default; negative is INVALID_ARGUMENT; large is clamped.
StatusOr<int> PageSize(int32_t page_size, uint32_t max_page_size);

}  // namespace vscan::api
