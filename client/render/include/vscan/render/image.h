#pragma once
// An 8-bit RGB image, rows top to bottom.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vscan::render {

struct Image {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3 bytes

  Image() = default;
  Image(uint32_t w, uint32_t h) : width(w), height(h), rgb(size_t{w} * h * 3, 0) {}

  // Pixel (x, y), y counted from the top row.
  std::array<uint8_t, 3> At(uint32_t x, uint32_t y) const;
};

}  // namespace vscan::render
