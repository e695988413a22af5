#pragma once
// A small vscand world for service-layer tests, without gRPC: the real store in a temporary
// directory (scenes, robots, clouds, jobs, blobs), the registries, worker pools and a
// ServiceContext over them.

#include <filesystem>
#include <memory>
#include <string>

#include "jobs/worker_pool.h"
#include "robot_registry/robot_registry.h"
#include "scenes/scene_registry.h"
#include "service/context/service_context.h"
#include "store/blob_store.h"
#include "store/catalogue.h"
#include "store/cloud_catalogue.h"
#include "store/database.h"
#include "store/job_catalogue.h"
#include "store/robot_catalogue.h"
#include "vscan/common/mesh.h"
#include "vscan_test/temp_dir.h"

namespace vscan::service::testing {

class ServiceWorld {
 public:
  explicit ServiceWorld(ServerOptions options = {});

  ServiceContext& context() { return *context_; }
  store::BlobStore& blobs() { return *blobs_; }
  store::CloudCatalogue& clouds() { return *clouds_; }
  store::JobCatalogue& jobs() { return *jobs_; }
  const std::filesystem::path& data_dir() const { return dir_.path(); }

  // mesh (metres) stored as a client's upload named name; its mesh id.
  std::string AddMesh(const TriangleMesh& mesh, const std::string& name);
  // A scene with nothing in it; with a rotary table at the origin when table is set.
  std::string EmptyScene(bool table = false);
  // A scene holding mesh (metres) at world_from_object; with a rotary table at the origin when
  // table is set (the object then stands on it).
  std::string SceneWith(const TriangleMesh& mesh, const Pose3& world_from_object, bool table = false);
  // A fixture robot ("ur5", "panda") mounted in scene_id at world_from_base.
  std::string Mount(const std::string& robot, const std::string& scene_id,
                    const Pose3& world_from_base = Pose3::Identity());

 private:
  test::TempDir dir_;
  ServerOptions options_;
  std::shared_ptr<store::Database> database_;
  std::unique_ptr<store::Catalogue> catalogue_;
  std::unique_ptr<store::RobotCatalogue> robot_catalogue_;
  std::unique_ptr<store::BlobStore> blobs_;
  std::unique_ptr<store::CloudCatalogue> clouds_;
  std::unique_ptr<store::JobCatalogue> jobs_;
  std::unique_ptr<scenes::SceneRegistry> scenes_;
  std::unique_ptr<robot_registry::RobotRegistry> robots_;
  jobs::WorkerPool workers_{1};
  RasterProvider raster_;
  std::unique_ptr<ServiceContext> context_;
};

// A square of side 2 * half_size in the plane z = 0, facing +z.
TriangleMesh FloorSquare(double half_size);

}  // namespace vscan::service::testing
