#pragma once
// 8-bit RGB images to and from PNG bytes in memory, through libpng.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vscan/common/status.h"

namespace vscan {

struct RgbPixels {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3 bytes, rows top to bottom
};

// True when bytes start with the eight-byte PNG signature.
bool HasPngSignature(std::string_view bytes);

// rgb holds width * height * 3 bytes, rows top to bottom. InvalidArgument for a wrong size or no
// pixels, DataLoss when libpng fails.
StatusOr<std::string> EncodePng(uint32_t width, uint32_t height, std::span<const uint8_t> rgb);

// Any 8-bit or 16-bit PNG as 8-bit RGB (alpha dropped, grey expanded, palettes resolved).
// InvalidArgument without the PNG signature, DataLoss for a damaged or truncated stream.
StatusOr<RgbPixels> DecodePng(std::string_view bytes);

}  // namespace vscan
