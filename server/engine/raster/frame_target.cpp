#include "raster/frame_target.h"

#include <cstdio>
#include <string>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {
namespace {

GLenum DepthInternalFormat(DepthFormat format) {
  return format == DepthFormat::kFixed24 ? GL_DEPTH_COMPONENT24 : GL_DEPTH_COMPONENT32F;
}

void Allocate(GLuint& renderbuffer, GLenum format, uint32_t width, uint32_t height) {
  if (renderbuffer == 0) glGenRenderbuffers(1, &renderbuffer);
  glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer);
  glRenderbufferStorage(GL_RENDERBUFFER, format, static_cast<GLsizei>(width), static_cast<GLsizei>(height));
}

}  // namespace

FrameTarget::~FrameTarget() {
  const GLuint renderbuffers[] = {faces_, colour_, radiance_, depth_};
  glDeleteRenderbuffers(4, renderbuffers);
  if (framebuffer_ != 0) glDeleteFramebuffers(1, &framebuffer_);
}

Status FrameTarget::Prepare(uint32_t width, uint32_t height, DepthFormat depth, bool colour, bool radiance) {
  if (framebuffer_ == 0) glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  const bool resized = width != width_ || height != height_;
  const GLenum depth_format = DepthInternalFormat(depth);
  if (resized) {
    width_ = height_ = 0;  // stays invalid if an allocation below fails
    has_colour_ = has_radiance_ = false;
    Allocate(faces_, GL_R32UI, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, kFaceAttachment, GL_RENDERBUFFER, faces_);
  }
  if (resized || depth_format != depth_format_) {
    Allocate(depth_, depth_format, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    depth_format_ = depth_format;
  }
  if (colour && (resized || !has_colour_)) {
    Allocate(colour_, GL_RGBA8, width, height);
    has_colour_ = true;
  }
  if (radiance && (resized || !has_radiance_)) {
    Allocate(radiance_, GL_R32F, width, height);
    has_radiance_ = true;
  }
  // The colour and radiance attachments are attached only while a scan needs them.
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, kColourAttachment, GL_RENDERBUFFER, colour ? colour_ : 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, kRadianceAttachment, GL_RENDERBUFFER, radiance ? radiance_ : 0);
  RETURN_IF_ERROR(gl::CheckGl("raster: allocating the framebuffer"));
  width_ = width;
  height_ = height;

  // Fragment output location i goes to buffers[i].
  const GLenum buffers[] = {kFaceAttachment, colour ? kColourAttachment : GL_NONE, kRadianceAttachment};
  glDrawBuffers(radiance ? 3 : colour ? 2 : 1, buffers);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof(code), "0x%04X", status);
    return Internal(std::string("raster: framebuffer incomplete (status ") + code + ")");
  }
  return gl::CheckGl("raster: binding the framebuffer");
}

}  // namespace vscan::raster
