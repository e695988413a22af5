#pragma once
// An RGBA8 colour + 24-bit depth framebuffer of one size, bound for drawing while it lives.

#include <cstdint>
#include <memory>

#include "vscan/gl/gl_api.h"
#include "vscan/common/status.h"
#include "vscan/render/image.h"

namespace vscan::render {

class OffscreenTarget {
 public:
  // INVALID_ARGUMENT naming --width or --height when the context cannot hold the size.
  static StatusOr<std::unique_ptr<OffscreenTarget>> Create(uint32_t width, uint32_t height);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  // The colour attachment, rows flipped so that the top row comes first.
  StatusOr<Image> ReadRgb() const;

 private:
  OffscreenTarget(uint32_t width, uint32_t height);
  uint32_t width_, height_;
  GLuint framebuffer_ = 0, colour_ = 0, depth_ = 0;
};

}  // namespace vscan::render
