#pragma once
// What every request of the service layer works with: the scene and robot registries, the stored
// clouds and the blobs, the worker pools, the options, the renderer, scan admission, the Bullet
// shapes of collision checks and the localizer's part models.

#include <memory>

#include "jobs/worker_pool.h"
#include "robot_registry/robot_registry.h"
#include "scenes/scene_registry.h"
#include "service/context/raster_provider.h"
#include "service/context/scan_admission.h"
#include "service/context/server_options.h"
#include "store/blob_store.h"
#include "store/cloud_catalogue.h"

namespace vscan::collision {
class ShapeCache;
}
namespace vscan::localization {
class PartModelCache;
}

namespace vscan::service {

class DatasetDirectories;

struct ServiceContext {
  ServiceContext(scenes::SceneRegistry& registry, jobs::WorkerPool& workers, jobs::WorkerPool& call_workers,
                 const ServerOptions& options, robot_registry::RobotRegistry& robots, RasterProvider& raster,
                 store::CloudCatalogue& clouds, store::BlobStore& blobs);
  ~ServiceContext();

  scenes::SceneRegistry& registry;
  jobs::WorkerPool& workers;       // scans and uploads
  jobs::WorkerPool& call_workers;  // blocking unary calls
  const ServerOptions& options;
  robot_registry::RobotRegistry& robots;
  RasterProvider& raster;
  store::CloudCatalogue& clouds;
  store::BlobStore& blobs;
  ScanAdmission scans;
  // Bullet shapes of scene meshes and links, shared by every collision check of the server.
  std::shared_ptr<collision::ShapeCache> shapes;
  // The localizer's part models (samples and pair tables), kept between Localize calls.
  std::shared_ptr<localization::PartModelCache> part_models;
  // The dataset jobs' directories; null where no server runs them (tests).
  DatasetDirectories* dataset_directories = nullptr;
};

}  // namespace vscan::service
