#pragma once
// A headless EGL display with an OpenGL core context, current on the thread that created it.
// No window or surface: rendering goes to framebuffer objects only.

#include <memory>
#include <string>

#include "vscan/common/status.h"

namespace vscan::raster {

class EglContext {
 public:
  // Tries the surfaceless Mesa platform, then each EGL device (GPU vendors' EGL), then the default
  // display; asks for OpenGL 4.5 core, then 3.3 core. Unavailable when none of them works.
  static StatusOr<std::unique_ptr<EglContext>> CreateCurrent();
  // Releases and destroys the context; call on the creating thread.
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

}  // namespace vscan::raster
