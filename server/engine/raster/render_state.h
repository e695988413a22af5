#pragma once
// What the render thread keeps between requests: the context's limits, the shader programs,
// the framebuffer and the uploaded scenes. Touched only on the render thread.

#include <cstdint>
#include <memory>
#include <string>

#include "raster/frame_target.h"
#include "raster/material_table.h"
#include "raster/raster_renderer.h"
#include "raster/scan_programs.h"
#include "raster/scene_cache.h"
#include "vscan/common/status.h"

namespace vscan::raster {

struct GlCaps {
  std::string renderer, version;
  int major = 0, minor = 0;
  // glClipControl (GL 4.5 or ARB_clip_control): window depth d = z_clip / w_clip directly, which
  // a reversed float depth buffer needs for its precision.
  bool clip_control = false;
  uint32_t max_side = 0;
  int64_t max_buffer_texels = 0;
};

struct RenderState {
  GlCaps caps;
  ScanPrograms programs;
  FrameTarget target;
  MaterialTable materials;
  SceneCache scenes;

  // Needs a current context; sets the state every scan relies on.
  static StatusOr<std::unique_ptr<RenderState>> Create(const RendererOptions& options);

 private:
  RenderState(GlCaps caps, ScanPrograms programs, const RendererOptions& options);
};

}  // namespace vscan::raster
