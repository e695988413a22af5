#pragma once
// One OpenGL renderer per server, created on first use; a machine without EGL answers UNAVAILABLE.

#include <memory>
#include <mutex>

#include "vscan/common/status.h"

namespace vscan::raster {
class RasterRenderer;
}

namespace vscan::service {

class RasterProvider {
 public:
  RasterProvider();
  ~RasterProvider();
  StatusOr<raster::RasterRenderer*> Get();

 private:
  std::mutex mutex_;
  bool tried_ = false;
  Status error_;
  std::unique_ptr<raster::RasterRenderer> renderer_;
};

}  // namespace vscan::service
