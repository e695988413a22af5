#include "service/context/raster_provider.h"

#include <spdlog/spdlog.h>

#include "raster/raster_renderer.h"

namespace vscan::service {

RasterProvider::RasterProvider() = default;
RasterProvider::~RasterProvider() = default;

StatusOr<raster::RasterRenderer*> RasterProvider::Get() {
  std::lock_guard lock(mutex_);
  if (!tried_) {
    tried_ = true;
    auto renderer = raster::RasterRenderer::Create();
    if (renderer.ok()) {
      renderer_ = std::move(renderer).value();
      spdlog::info("raster backend: {} ({}, {})", renderer_->gl_renderer(), renderer_->gl_version(),
                   renderer_->platform());
    } else {
      error_ = Unavailable("backend: raster scanning needs OpenGL through EGL: " + renderer.status().message());
      spdlog::warn("{}", error_.message());
    }
  }
  if (!renderer_) return error_;
  return renderer_.get();
}

}  // namespace vscan::service
