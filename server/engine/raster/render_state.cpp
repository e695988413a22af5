#include "raster/render_state.h"

#include <algorithm>
#include <string_view>
#include <utility>

#include "vscan/gl/gl_check.h"

namespace vscan::raster {
namespace {

std::string GlString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s != nullptr ? s : "";
}

bool HasGlExtension(std::string_view name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e != nullptr && name == e) return true;
  }
  return false;
}

StatusOr<GlCaps> QueryCaps() {
  GlCaps caps;
  caps.renderer = GlString(GL_RENDERER);
  caps.version = GlString(GL_VERSION);
  glGetIntegerv(GL_MAJOR_VERSION, &caps.major);
  glGetIntegerv(GL_MINOR_VERSION, &caps.minor);
  if (caps.major * 10 + caps.minor < 33) {
    return Unavailable("raster: OpenGL 3.3 core or newer needed, the context is " + caps.version);
  }
  caps.clip_control = caps.major * 10 + caps.minor >= 45 || HasGlExtension("GL_ARB_clip_control");
  GLint renderbuffer = 0, viewport[2] = {};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  caps.max_side = static_cast<uint32_t>(std::max(0, std::min({renderbuffer, viewport[0], viewport[1]})));
  GLint texels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
  caps.max_buffer_texels = texels;
  RETURN_IF_ERROR(gl::CheckGl("raster: querying the context"));
  return caps;
}

}  // namespace

RenderState::RenderState(GlCaps caps_in, ScanPrograms programs_in, const RendererOptions& options)
    : caps(std::move(caps_in)),
      programs(std::move(programs_in)),
      scenes(options.max_cached_scenes, options.max_cached_bytes, caps.max_buffer_texels) {}

StatusOr<std::unique_ptr<RenderState>> RenderState::Create(const RendererOptions& options) {
  ASSIGN_OR_RETURN(GlCaps caps, QueryCaps());
  if (caps.clip_control) glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  glDisable(GL_DITHER);  // dithering would perturb the colour method's codes
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  ASSIGN_OR_RETURN(ScanPrograms programs, ScanPrograms::Build());
  RETURN_IF_ERROR(gl::CheckGl("raster: setting up the context"));
  return std::unique_ptr<RenderState>(new RenderState(std::move(caps), std::move(programs), options));
}

}  // namespace vscan::raster
