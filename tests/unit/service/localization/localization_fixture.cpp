#include "localization_fixture.h"

#include <fstream>
#include <iterator>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>

#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"

namespace vscan::service::testing {
namespace {

std::string StorePart(ServiceWorld& world, const char* file, double metres_per_unit) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  scenes::MeshUpload upload;
  upload.name = file;
  upload.format = geometry::MeshFileFormat::kStl;
  upload.metres_per_unit = metres_per_unit;
  auto stored = world.context().registry.AddMesh(bytes, upload);
  EXPECT_TRUE(stored.ok()) << file << ": " << stored.status().ToString();
  return stored.ok() ? stored->mesh_id : "";
}

}  // namespace

std::array<std::string, 3> StoreFixtureParts(ServiceWorld& world) {
  return {StorePart(world, "angle_block.STL", 0.0254), StorePart(world, "round.stl", 0.01),
          StorePart(world, "plate_holes.STL", 0.001)};
}

PinsAndBlocks ScanPinsBesideBlocks() {
  using localization::testing::FixturePart;
  PinsAndBlocks scene;
  auto pin = std::make_shared<TriangleMesh>(*localization::testing::LoadPart(FixturePart::kRound));
  for (auto& v : pin->vertices) v *= static_cast<float>(kPinScale);
  const double radius = 0.0254 * kPinScale;
  const auto blocks = localization::testing::LyingParts({{FixturePart::kAngleBlock, 6}}, 0.2, 4);
  std::vector<raycast::SceneInstance> instances = localization::testing::FloorInstances(blocks, kPinFloor);
  for (const auto& block : blocks) scene.blocks.push_back(block.world_from_part);
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(-0.12, 0.125), Eigen::Vector2d(0.03, 0.125),
                                    Eigen::Vector2d(-0.04, -0.13)}) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(at.x(), at.y(), radius);
    scene.pins.push_back(pose);
    instances.push_back({pin, pose, 1.0, static_cast<uint32_t>(100 + scene.pins.size())});
  }
  auto built = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(built.ok()) << built.status().ToString();
  if (!built.ok()) return scene;
  raycast::ScanOptions options;
  options.fields = kFieldPosition | kFieldNormal;
  auto scan = raycast::Scan(**built, sensor::CameraFromFov(1280, 960, 50, 0.05, 4 * kPinFloor),
                            localization::testing::FloorSensorPose(kPinFloor), options);
  EXPECT_TRUE(scan.ok()) << scan.status().ToString();
  if (scan.ok()) scene.scan = std::move(*scan);
  return scene;
}

localization::PartSymmetries PinSymmetries() {
  using localization::testing::FixturePart;
  localization::PartSymmetries symmetries = localization::testing::SymmetriesOf(FixturePart::kRound);
  for (Pose3& flip : symmetries.discrete) flip.translation() *= kPinScale;
  for (auto& axis : symmetries.continuous) axis.point *= kPinScale;
  return symmetries;
}

}  // namespace vscan::service::testing
