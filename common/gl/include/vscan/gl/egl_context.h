#pragma once
// A headless EGL display with an OpenGL core context, for drawing into framebuffer objects
// (no window, no surface). Threading: the context is current on the thread that created it and
// must be used and destroyed on that thread only. No GL or EGL header is included here.

#include <memory>
#include <string>

#include "vscan/common/status.h"

namespace vscan::gl {

class EglContext {
 public:
  // Tries the surfaceless Mesa platform, then each EGL device (GPU vendors' EGL), then the default
  // display; asks for OpenGL 4.5 core, then 3.3 core, and makes the context current on the calling
  // thread. Unavailable ("no EGL display (...)" or "no usable OpenGL context (...)") when none works.
  static StatusOr<std::unique_ptr<EglContext>> CreateCurrent();
  // Releases and destroys the context; call on the creating thread, after deleting its GL objects.
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // Which display was used, e.g. "surfaceless Mesa, EGL 1.5".
  const std::string& platform() const;

  struct Impl;

 private:
  explicit EglContext(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace vscan::gl
