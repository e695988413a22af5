#include "vscan/render/image.h"

namespace vscan::render {

std::array<uint8_t, 3> Image::At(uint32_t x, uint32_t y) const {
  const size_t at = (size_t{y} * width + x) * 3;
  return {rgb[at], rgb[at + 1], rgb[at + 2]};
}

}  // namespace vscan::render
