#pragma once
// What the gRPC services share: the scene and robot registries, the worker pool, the options.

#include <atomic>

#include "api/raster_provider.h"
#include "api/server_options.h"
#include "api/stall_watchdog.h"
#include "jobs/worker_pool.h"
#include "robots/robot_registry.h"
#include "scenes/scene_registry.h"

namespace vscan::api {

struct ServiceContext {
  scenes::SceneRegistry& registry;
  jobs::WorkerPool& workers;
  const ServerOptions& options;
  robots::RobotRegistry& robots;
  RasterProvider& raster;
  std::atomic<uint32_t> active_scans{0};
  // Cancels streams whose client stopped reading (--stalled-reader-seconds); null watches nothing.
  StallWatchdog* stalled_readers = nullptr;
};

}  // namespace vscan::api
