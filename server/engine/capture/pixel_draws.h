#pragma once
// Counter-based uniform draws keyed by (seed, stream, pixel): the same seed gives the same
// artefacts bit for bit, whatever the thread that handles a pixel.

#include <cstdint>

namespace vscan::capture {

enum class DrawStream : uint64_t { kOutlierPick = 1, kOutlierRay = 2, kFlyingPixel = 3 };

class PixelDraws {
 public:
  PixelDraws(uint64_t seed, DrawStream stream, uint64_t pixel)
      : base_(Mix(Mix(seed ^ (static_cast<uint64_t>(stream) * 0xd1b54a32d192ed03ull)) ^ pixel)) {}

  // In [0, 1).
  double Uniform() { return static_cast<double>(Mix(base_ + counter_++) >> 11) * 0x1.0p-53; }

 private:
  static uint64_t Mix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  }

  uint64_t base_;
  uint64_t counter_ = 0;
};

}  // namespace vscan::capture
