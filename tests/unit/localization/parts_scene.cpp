#include "parts_scene.h"

#include <fstream>
#include <iterator>
#include <numbers>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "geometry/mesh_import.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan_test/meshes.h"

namespace vscan::localization::testing {

std::shared_ptr<const TriangleMesh> AngleBlock() {
  static const std::shared_ptr<const TriangleMesh> mesh = [] {
    std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/angle_block.STL", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto imported = geometry::ImportMesh(bytes, geometry::MeshFileFormat::kStl, 0.0254);
    EXPECT_TRUE(imported.ok()) << imported.status().ToString();
    return std::make_shared<const TriangleMesh>(imported.ok() ? std::move(*imported) : TriangleMesh{});
  }();
  return mesh;
}

std::vector<Pose3> StandingPoses(size_t count) {
  // The part's y axis (0 to 25.4 mm) becomes world z, so it stands on z = 0; its z axis (-34 to 0 mm)
  // becomes world y.
  Pose3 standing = Pose3::Identity();
  standing.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector2d places[] = {{-0.06, -0.045}, {0.05, -0.05}, {0.0, 0.04}, {0.065, 0.045}};
  const double turns_deg[] = {20, 145, 260, 75};
  std::vector<Pose3> poses;
  for (size_t i = 0; i < count && i < 4; ++i) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(turns_deg[i] * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(places[i].x(), places[i].y(), 0);
    poses.push_back(pose * standing);
  }
  return poses;
}

PointCloud ScanParts(const std::vector<Pose3>& world_from_part, double plate_side) {
  std::vector<raycast::SceneInstance> instances;
  for (size_t i = 0; i < world_from_part.size(); ++i) {
    instances.push_back({AngleBlock(), world_from_part[i], 1.0, static_cast<uint32_t>(i + 1)});
  }
  instances.push_back({test::Share(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), plate_side / 2)),
                       Pose3::Identity(), 1.0, 0});
  auto scene = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  if (!scene.ok()) return {};
  auto sensor = PoseFromLookAt(Eigen::Vector3d(0.02, -0.22, 0.32), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                               "sensor");
  EXPECT_TRUE(sensor.ok());
  raycast::ScanOptions options;
  options.fields = kFieldPosition | kFieldNormal;
  auto cloud = raycast::Scan(**scene, sensor::CameraFromFov(640, 480, 40, 0.05, 2.0), *sensor, options);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  return cloud.ok() ? std::move(*cloud) : PointCloud{};
}

}  // namespace vscan::localization::testing
