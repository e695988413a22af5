#pragma once
// The most rows one List call returns, however many it asks for (docs/OPERATIONS.md, fixed bounds).

namespace vscan::store {

inline constexpr int kMaxListLimit = 1000;

}  // namespace vscan::store
