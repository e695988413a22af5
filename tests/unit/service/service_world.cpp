#include "service_world.h"

#include <sstream>

#include <gtest/gtest.h>

#include "robot_fixtures.h"
#include "vscan_test/meshes.h"

namespace vscan::service::testing {
namespace {

std::string ObjText(const TriangleMesh& mesh) {
  std::ostringstream obj;
  obj.precision(17);
  for (const Eigen::Vector3f& v : mesh.vertices) obj << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& f : mesh.triangles) obj << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
  return obj.str();
}

template <typename T>
T Must(StatusOr<T> value) {
  if (!value.ok()) ADD_FAILURE() << value.status().ToString();
  return std::move(value).value();
}

}  // namespace

ServiceWorld::ServiceWorld(ServerOptions options) : options_(std::move(options)) {
  options_.data_dir = dir_.path().string();
  database_ = Must(store::Database::Open(dir_.path() / "catalogue.sqlite"));
  catalogue_ = std::make_unique<store::Catalogue>(database_);
  robot_catalogue_ = std::make_unique<store::RobotCatalogue>(database_);
  blobs_ = std::make_unique<store::BlobStore>(dir_.path() / "blobs");
  EXPECT_TRUE(blobs_->Open().ok());
  scenes_ = std::make_unique<scenes::SceneRegistry>(*catalogue_, *blobs_);
  robots_ = std::make_unique<robot_registry::RobotRegistry>(*robot_catalogue_, *blobs_, 64u << 20);
  clouds_ = std::make_unique<store::CloudCatalogue>(database_);
  jobs_ = std::make_unique<store::JobCatalogue>(database_);
  context_ = std::make_unique<ServiceContext>(*scenes_, workers_, workers_, options_, *robots_, raster_, *clouds_,
                                              *blobs_);
}

std::string ServiceWorld::EmptyScene(bool table) {
  const store::SceneRecord scene = Must(catalogue_->CreateScene("cell"));
  if (table) {
    store::TableRecord record;
    record.enabled = true;
    EXPECT_TRUE(catalogue_->SetTable(scene.scene_id, record).ok());
  }
  return scene.scene_id;
}

std::string ServiceWorld::AddMesh(const TriangleMesh& mesh, const std::string& name) {
  scenes::MeshUpload upload;
  upload.name = name;
  upload.format = geometry::MeshFileFormat::kObj;
  return Must(scenes_->AddMesh(ObjText(mesh), upload)).mesh_id;
}

std::string ServiceWorld::SceneWith(const TriangleMesh& mesh, const Pose3& world_from_object, bool table) {
  store::ObjectRecord object;
  object.scene_id = EmptyScene(table);
  object.mesh_id = AddMesh(mesh, "object");
  object.label = "object";
  object.on_table = table;
  object.pose = world_from_object.matrix();
  EXPECT_TRUE(catalogue_->AddObject(object).ok());
  return object.scene_id;
}

std::string ServiceWorld::Mount(const std::string& robot_name, const std::string& scene_id,
                                const Pose3& world_from_base) {
  const auto& fixture = robot::testing::Fixture(robot_name);
  robot_registry::RobotUpload upload;
  upload.urdf_path = fixture.urdf_path;
  upload.base_link = fixture.base_link;
  upload.tip_link = fixture.tip_link;
  upload.files = robot::testing::FixtureBundleFiles(robot_name);
  const auto robot = Must(robots_->AddRobot(upload));
  store::MountRecord mount;
  mount.scene_id = scene_id;
  mount.robot_id = robot.robot_id;
  mount.base_pose = world_from_base.matrix();
  return Must(robots_->AddMount(mount)).first.mount_id;
}

TriangleMesh FloorSquare(double half_size) {
  return test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), half_size);
}

}  // namespace vscan::service::testing
