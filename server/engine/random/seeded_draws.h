#pragma once
// Seeded draws from SplitMix64's mixer: the same seed gives the same bits on every machine and
// thread, which scans, encoder noise, IK restarts and campaign steps all rely on.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace vscan::random {

inline constexpr uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;

// SplitMix64 (Steele, Lea, Flood 2014): the generator's step and output mix, as a pure function.
constexpr uint64_t SplitMix64(uint64_t x) {
  x += kGoldenGamma;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// The top 53 bits as a double in [0, 1).
constexpr double UnitInterval(uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }
// The top 53 bits as a double in (0, 1], for log().
constexpr double UnitIntervalAboveZero(uint64_t bits) { return static_cast<double>((bits >> 11) + 1) * 0x1.0p-53; }

// Counter-based draws: draw k depends only on (key, k), so no state is shared between keys.
class KeyedDraws {
 public:
  explicit KeyedDraws(uint64_t key) : key_(key) {}
  uint64_t NextBits() { return SplitMix64(key_ + counter_++); }
  double Uniform() { return UnitInterval(NextBits()); }
  double UniformAboveZero() { return UnitIntervalAboveZero(NextBits()); }

 private:
  uint64_t key_;
  uint64_t counter_ = 0;
};

// Standard normal deviates for one (seed, key), e.g. a point's or a pixel's: deviate k depends only
// on (seed, key, k) (Box-Muller over KeyedDraws).
class KeyedNormals {
 public:
  KeyedNormals(uint64_t seed, uint64_t key) : draws_(SplitMix64(SplitMix64(seed) ^ key)) {}

  double Next() {
    if (has_spare_) {
      has_spare_ = false;
      return radius_ * std::sin(angle_);  // the pair's second deviate, only paid for when asked for
    }
    // In (0, 1], so log() stays finite.
    const double u1 = draws_.UniformAboveZero(), u2 = draws_.UniformAboveZero();
    radius_ = std::sqrt(-2.0 * std::log(u1));
    angle_ = 2.0 * std::numbers::pi * u2;
    has_spare_ = true;
    return radius_ * std::cos(angle_);
  }

 private:
  KeyedDraws draws_;
  double radius_ = 0, angle_ = 0;
  bool has_spare_ = false;
};

// The sequential SplitMix64 generator, for one stream of draws from one seed.
class SplitMix64Stream {
 public:
  explicit SplitMix64Stream(uint64_t seed) : state_(seed) {}
  uint64_t NextBits() {
    const uint64_t bits = SplitMix64(state_);
    state_ += kGoldenGamma;
    return bits;
  }
  double Uniform() { return UnitInterval(NextBits()); }

 private:
  uint64_t state_;
};

}  // namespace vscan::random
