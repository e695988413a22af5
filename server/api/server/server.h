#pragma once
// vscand as an object: opens the store, registers the services, serves until shut down.

#include <memory>
#include <string>

#include "service/context/server_options.h"
#include "vscan/common/status.h"

namespace vscan::scenes {
class SceneRegistry;
}
namespace vscan::store {
class BlobStore;
class CloudCatalogue;
}
namespace vscan::robot_registry {
class RobotRegistry;
}
namespace vscan::service {
class DatasetDirectories;
}

namespace vscan::api {

class JobTracker;

class Server {
 public:
  ~Server();
  // Opens the data directory and starts listening; the bound port is in port().
  static StatusOr<std::unique_ptr<Server>> Start(const service::ServerOptions& options);
  int port() const;
  // What the services read, for the web view, which reads them too.
  scenes::SceneRegistry& scene_registry();
  JobTracker& job_tracker();
  store::CloudCatalogue& cloud_catalogue();
  store::BlobStore& blobs();
  robot_registry::RobotRegistry& robots();
  service::DatasetDirectories& dataset_directories();
  // Stops accepting calls, cancels running ones after grace_seconds, and waits for them.
  void Shutdown(double grace_seconds);

  struct Impl;

 private:
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Writes port to path (what --port-file promises once vscand serves).
Status WritePortFile(const std::string& path, int port);

}  // namespace vscan::api
