#pragma once
// The offscreen framebuffer a scan renders into: face ids (R32UI), an optional RGBA8 colour
// attachment, an optional R32F radiance attachment (the returned light's direct term), and a depth
// buffer. Reallocated only when the size or formats change.

#include <cstdint>

#include "raster/raster_scanner.h"
#include "vscan/common/status.h"
#include "vscan/gl/gl_api.h"

namespace vscan::raster {

inline constexpr GLenum kFaceAttachment = GL_COLOR_ATTACHMENT0;
inline constexpr GLenum kColourAttachment = GL_COLOR_ATTACHMENT1;
inline constexpr GLenum kRadianceAttachment = GL_COLOR_ATTACHMENT2;

class FrameTarget {
 public:
  FrameTarget() = default;
  FrameTarget(const FrameTarget&) = delete;
  FrameTarget& operator=(const FrameTarget&) = delete;
  ~FrameTarget();

  // Sizes the attachments, binds the framebuffer for drawing and reading, and sets the draw buffers.
  Status Prepare(uint32_t width, uint32_t height, DepthFormat depth, bool colour, bool radiance);

 private:
  GLuint framebuffer_ = 0;
  GLuint faces_ = 0, colour_ = 0, radiance_ = 0, depth_ = 0;
  uint32_t width_ = 0, height_ = 0;
  GLenum depth_format_ = 0;
  bool has_colour_ = false, has_radiance_ = false;
};

}  // namespace vscan::raster
