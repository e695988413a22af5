#include "vscan/gl/gl_check.h"

#include <string>

#include "vscan/gl/gl_api.h"

namespace vscan::gl {
namespace {

const char* GlErrorName(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "unknown GL error";
  }
}

}  // namespace

Status CheckGl(std::string_view what) {
  GLenum first = GL_NO_ERROR;
  bool out_of_memory = false;
  for (GLenum error = glGetError(); error != GL_NO_ERROR; error = glGetError()) {
    if (first == GL_NO_ERROR) first = error;
    out_of_memory |= error == GL_OUT_OF_MEMORY;
  }
  if (first == GL_NO_ERROR) return Status::Ok();
  if (out_of_memory) return ResourceExhausted(std::string(what) + ": out of GPU memory");
  return Internal(std::string(what) + ": " + GlErrorName(first));
}

}  // namespace vscan::gl
