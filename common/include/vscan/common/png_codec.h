#pragma once
// Images to and from PNG bytes in memory, through libpng: 8-bit RGB pictures, and 8-bit or 16-bit
// greyscale for values (depth, masks, instance indices).

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

// One channel of 8 or 16 bits per pixel; 8-bit values are widened, never scaled.
struct GrayPixels {
  uint32_t width = 0;
  uint32_t height = 0;
  int bit_depth = 0;             // 8 or 16
  std::vector<uint16_t> values;  // width * height values, rows top to bottom
};

// An 8-bit greyscale PNG of width * height values, rows top to bottom. Errors as EncodePng.
StatusOr<std::string> EncodeGray8Png(uint32_t width, uint32_t height, std::span<const uint8_t> values);
// A 16-bit greyscale PNG of width * height values; the file holds them big-endian as PNG requires.
StatusOr<std::string> EncodeGray16Png(uint32_t width, uint32_t height, std::span<const uint16_t> values);

// An 8-bit or 16-bit greyscale PNG without alpha, values as stored. InvalidArgument without the
// signature or for any other colour type or depth (nothing is converted), DataLoss as DecodePng.
StatusOr<GrayPixels> DecodeGrayPng(std::string_view bytes);

}  // namespace vscan
