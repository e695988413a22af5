#pragma once
// A constexpr two-way map between the values of two enums (or an enum and stored integer codes),
// with the compile-time checks that make it total: each side distinct, and a contiguous range of
// values covered.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>

namespace vscan::store {

template <typename A, typename B, size_t N>
class EnumMap {
 public:
  constexpr explicit EnumMap(std::array<std::pair<A, B>, N> pairs) : pairs_(pairs) {}

  constexpr std::optional<B> Forward(A a) const {
    for (const auto& [x, y] : pairs_) {
      if (x == a) return y;
    }
    return std::nullopt;
  }
  constexpr std::optional<A> Backward(B b) const {
    for (const auto& [x, y] : pairs_) {
      if (y == b) return x;
    }
    return std::nullopt;
  }

  // No value appears twice on either side.
  constexpr bool Distinct() const {
    for (size_t i = 0; i < N; ++i) {
      for (size_t j = i + 1; j < N; ++j) {
        if (pairs_[i].first == pairs_[j].first || pairs_[i].second == pairs_[j].second) return false;
      }
    }
    return true;
  }
  // Every A from first to last (by underlying value) has an entry, and nothing else does.
  constexpr bool CoversFirst(A first, A last) const { return Covers<0>(Value(first), Value(last)); }
  constexpr bool CoversSecond(B first, B last) const { return Covers<1>(Value(first), Value(last)); }

 private:
  template <typename T>
  static constexpr int64_t Value(T t) {
    return static_cast<int64_t>(t);
  }
  template <int Side>
  constexpr bool Covers(int64_t first, int64_t last) const {
    if (last - first + 1 != static_cast<int64_t>(N) || !Distinct()) return false;
    for (const auto& pair : pairs_) {
      const int64_t v = Value(std::get<Side>(pair));
      if (v < first || v > last) return false;
    }
    return true;
  }

  std::array<std::pair<A, B>, N> pairs_;
};

}  // namespace vscan::store
