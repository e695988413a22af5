#pragma once
// The small world scan_request_fuzzer scans, built once: a temporary data directory with the real
// store, a scene with a cube and the bunny on a rotary table, a Panda mounted in it with its links
// visible, and mounts that no request can create any more (see scan_fuzz_world.cpp).

#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "jobs/worker_pool.h"
#include "robot_registry/robot_registry.h"
#include "scenes/scene_registry.h"
#include "service/context/raster_provider.h"
#include "service/context/server_options.h"
#include "service/context/service_context.h"
#include "store/blob_store.h"
#include "store/catalogue.h"
#include "store/cloud_catalogue.h"
#include "store/robot_catalogue.h"

namespace vscan::fuzz {

// Rays per scan: small, so that each run takes milliseconds.
inline constexpr uint64_t kMaxRaysPerScan = 96 * 96;

struct ScanFuzzWorld {
  std::filesystem::path data_dir;
  service::ServerOptions options;
  std::unique_ptr<store::Catalogue> catalogue;
  std::unique_ptr<store::BlobStore> blobs;
  std::unique_ptr<scenes::SceneRegistry> scenes;
  std::unique_ptr<store::RobotCatalogue> robot_catalogue;
  std::unique_ptr<robot_registry::RobotRegistry> robots;
  std::unique_ptr<store::CloudCatalogue> clouds;
  std::unique_ptr<jobs::WorkerPool> workers;
  service::RasterProvider raster;
  std::unique_ptr<service::ServiceContext> context;

  std::string scene_id;
  // Mount ids by the names seeds use for them in robot.mount_id; other names get the Panda's.
  std::map<std::string, std::string> mounts;
  std::string default_mount;
};

// The world, built on first use (aborting with a message if it cannot be) and kept for the
// process's lifetime; its directory is removed at exit.
ScanFuzzWorld& World();

}  // namespace vscan::fuzz
