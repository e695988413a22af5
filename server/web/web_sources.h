#pragma once
// What the web view reads: the same registries and stores the gRPC services use, owned by the
// server. Null members are not served (their endpoints answer 404).

namespace vscan::scenes {
class SceneRegistry;
}
namespace vscan::api {
class JobTracker;
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

namespace vscan::web {

struct WebSources {
  scenes::SceneRegistry* scenes = nullptr;
  api::JobTracker* jobs = nullptr;
  store::CloudCatalogue* clouds = nullptr;
  store::BlobStore* blobs = nullptr;
  robot_registry::RobotRegistry* robots = nullptr;
  service::DatasetDirectories* datasets = nullptr;
};

}  // namespace vscan::web
