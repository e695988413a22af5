#pragma once
// An OpenGL renderer on its own thread. A GL context belongs to one thread, so every request
// is queued to the render thread and run there in order; callers may be on any thread.
// GL and EGL stay inside the .cpp files.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "vscan/common/status.h"

namespace vscan::raster {

// The render thread's GL state (programs, framebuffer, uploaded scenes); see render_state.h.
struct RenderState;

struct RendererOptions {
  // Uploaded scenes kept on the GPU, least recently used dropped first.
  size_t max_cached_scenes = 8;
  uint64_t max_cached_bytes = uint64_t{1} << 30;
};

class RasterRenderer {
 public:
  // Starts the render thread and creates the headless context on it; Unavailable without EGL/GL.
  static StatusOr<std::unique_ptr<RasterRenderer>> Create(const RendererOptions& options = {});
  // Finishes the queued work, then releases the GL objects and the context on the render thread.
  ~RasterRenderer();
  RasterRenderer(const RasterRenderer&) = delete;
  RasterRenderer& operator=(const RasterRenderer&) = delete;

  const std::string& gl_renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  const std::string& gl_version() const;   // GL_VERSION
  const std::string& platform() const;     // the EGL display used
  // Largest frame side the context can render (GL_MAX_RENDERBUFFER_SIZE and viewport limits).
  uint32_t max_side() const;

  // Runs work on the render thread with the context current and returns its Status; blocks the
  // caller. Requests run one at a time in arrival order; work must not call Run itself.
  Status Run(const std::function<Status(RenderState&)>& work);
  // Drops the scene cached under key, if any.
  void Evict(const std::string& key);
  size_t cached_scene_count();

  struct Impl;

 private:
  explicit RasterRenderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::raster
