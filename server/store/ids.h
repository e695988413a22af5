#pragma once
// Identifiers and timestamps of catalogue rows.

#include <cstdint>
#include <string>
#include <string_view>

namespace vscan::store {

// prefix + 16 random lowercase hex digits.
std::string NewId(std::string_view prefix);
// Wall-clock milliseconds since the Unix epoch.
int64_t NowMs();

}  // namespace vscan::store
