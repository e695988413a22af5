#include "offscreen_target.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "vscan/gl/gl_check.h"

namespace vscan::render {

OffscreenTarget::OffscreenTarget(uint32_t width, uint32_t height) : width_(width), height_(height) {}

OffscreenTarget::~OffscreenTarget() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteRenderbuffers(1, &depth_);
}

StatusOr<std::unique_ptr<OffscreenTarget>> OffscreenTarget::Create(uint32_t width, uint32_t height) {
  GLint max_renderbuffer = 0;
  GLint max_viewport[2] = {};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
  const auto max_width = static_cast<uint32_t>(std::min(max_renderbuffer, max_viewport[0]));
  const auto max_height = static_cast<uint32_t>(std::min(max_renderbuffer, max_viewport[1]));
  if (width == 0 || width > max_width) {
    return InvalidArgument("--width: " + std::to_string(width) + " is outside 1.." + std::to_string(max_width));
  }
  if (height == 0 || height > max_height) {
    return InvalidArgument("--height: " + std::to_string(height) + " is outside 1.." + std::to_string(max_height));
  }
  std::unique_ptr<OffscreenTarget> target(new OffscreenTarget(width, height));
  const auto w = static_cast<GLsizei>(width), h = static_cast<GLsizei>(height);
  glGenRenderbuffers(1, &target->colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, target->colour_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glGenRenderbuffers(1, &target->depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, target->depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
  glGenFramebuffers(1, &target->framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, target->framebuffer_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, target->colour_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, target->depth_);
  RETURN_IF_ERROR(gl::CheckGl("render: render target"));
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    return Internal("render: the framebuffer is incomplete");
  }
  glViewport(0, 0, w, h);
  return target;
}

StatusOr<Image> OffscreenTarget::ReadRgb() const {
  std::vector<uint8_t> rgba(size_t{width_} * height_ * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, static_cast<GLsizei>(width_), static_cast<GLsizei>(height_), GL_RGBA, GL_UNSIGNED_BYTE,
               rgba.data());
  RETURN_IF_ERROR(gl::CheckGl("render: read pixels"));
  Image image(width_, height_);
  for (uint32_t row = 0; row < height_; ++row) {
    const uint8_t* src = rgba.data() + size_t{height_ - 1 - row} * width_ * 4;
    uint8_t* dst = image.rgb.data() + size_t{row} * width_ * 3;
    for (uint32_t x = 0; x < width_; ++x) std::memcpy(dst + x * 3, src + x * 4, 3);
  }
  return image;
}

}  // namespace vscan::render
