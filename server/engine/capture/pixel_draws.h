#pragma once
// Counter-based uniform draws keyed by (seed, stream, pixel): the same seed gives the same
// artefacts bit for bit, whatever the thread that handles a pixel.

#include <cstdint>

#include "random/seeded_draws.h"

namespace vscan::capture {

enum class DrawStream : uint64_t { kOutlierPick = 1, kOutlierRay = 2, kFlyingPixel = 3, kIndirectLight = 4 };

class PixelDraws : public random::KeyedDraws {
 public:
  PixelDraws(uint64_t seed, DrawStream stream, uint64_t pixel)
      : KeyedDraws(random::SplitMix64(
            random::SplitMix64(seed ^ (static_cast<uint64_t>(stream) * 0xd1b54a32d192ed03ull)) ^ pixel)) {}
};

}  // namespace vscan::capture
