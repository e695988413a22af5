#include "parts_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <string>

#include <Eigen/Geometry>

#include "geometry/mesh_import.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"

namespace vscan::localization::testing {
namespace {

constexpr double kPi = std::numbers::pi;

// Scenes are fixtures: a missing file or a failed cast ends the program with the reason.
template <typename T>
T OrDie(StatusOr<T> value, const char* what) {
  if (!value.ok()) {
    std::fprintf(stderr, "%s: %s\n", what, value.status().ToString().c_str());
    std::abort();
  }
  return std::move(*value);
}

std::shared_ptr<const TriangleMesh> Import(const char* file, double metres_per_unit) {
  std::ifstream in(std::string(VSCAN_DATA_DIR) + "/parts/" + file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return std::make_shared<const TriangleMesh>(
      OrDie(geometry::ImportMesh(bytes, geometry::MeshFileFormat::kStl, metres_per_unit), file));
}

std::shared_ptr<const TriangleMesh> Square(double side) {
  auto mesh = std::make_shared<TriangleMesh>();
  const auto h = static_cast<float>(side / 2);
  mesh->vertices = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  mesh->triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

Pose3 LookingAtOrigin(const Eigen::Vector3d& eye) {
  return OrDie(PoseFromLookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), "sensor"), "sensor");
}

PointCloud Cast(const std::vector<raycast::SceneInstance>& instances, const Pose3& sensor,
                const sensor::PinholeCamera& camera) {
  const auto scene = OrDie(raycast::RaycastScene::Build(instances), "scene");
  raycast::ScanOptions options;
  options.fields = kFieldPosition | kFieldNormal;
  return OrDie(raycast::Scan(*scene, camera, sensor, options), "scan");
}

// The part axes that may face down when the part lies on the floor.
std::vector<Eigen::Vector3d> DownAxes(FixturePart part) {
  switch (part) {
    case FixturePart::kRound:
      return {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY()};
    case FixturePart::kPlateHoles:
      return {Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};
    case FixturePart::kAngleBlock:
      break;
  }
  return {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
          -Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()};
}

// A part's outline on the floor: a rectangle with its centre, unit axes and half sides.
struct Footprint {
  Eigen::Vector2d centre;
  std::array<Eigen::Vector2d, 2> axes;
  Eigen::Vector2d half;

  double Reach(const Eigen::Vector2d& direction) const {
    return half.x() * std::abs(axes[0].dot(direction)) + half.y() * std::abs(axes[1].dot(direction));
  }
};

// Separating axis test of two rectangles, with a gap of `margin` required.
bool Overlap(const Footprint& a, const Footprint& b, double margin) {
  for (const Footprint* f : {&a, &b}) {
    for (const auto& axis : f->axes) {
      if (std::abs(axis.dot(b.centre - a.centre)) > a.Reach(axis) + b.Reach(axis) + margin) return false;
    }
  }
  return true;
}

}  // namespace

std::shared_ptr<const TriangleMesh> LoadPart(FixturePart part) {
  static const std::array<std::shared_ptr<const TriangleMesh>, 3> meshes = {
      Import("angle_block.STL", 0.0254), Import("round.stl", 0.01), Import("plate_holes.STL", 0.001)};
  return meshes[static_cast<size_t>(part)];
}

PartSymmetries SymmetriesOf(FixturePart part) {
  PartSymmetries symmetries;
  if (part != FixturePart::kRound) return symmetries;
  // The tube's axis is the z axis (0 to 0.6096 m); the flip turns it about x through its middle.
  symmetries.continuous.push_back({Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero()});
  Pose3 flip = Pose3::Identity();
  flip.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  flip.translation() = Eigen::Vector3d(0, 0, 0.6096);
  symmetries.discrete.push_back(flip);
  return symmetries;
}

std::shared_ptr<const TriangleMesh> AngleBlock() { return LoadPart(FixturePart::kAngleBlock); }

std::vector<Pose3> StandingPoses(size_t count) {
  // The part's y axis (0 to 25.4 mm) becomes world z, so it stands on z = 0; its z axis (-34 to 0 mm)
  // becomes world y.
  Pose3 standing = Pose3::Identity();
  standing.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector2d places[] = {{-0.06, -0.045}, {0.05, -0.05}, {0.0, 0.04}, {0.065, 0.045}};
  const double turns_deg[] = {20, 145, 260, 75};
  std::vector<Pose3> poses;
  for (size_t i = 0; i < count && i < 4; ++i) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(turns_deg[i] * kPi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
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
  instances.push_back({Square(plate_side), Pose3::Identity(), 1.0, 0});
  return Cast(instances, LookingAtOrigin(Eigen::Vector3d(0.02, -0.22, 0.32)), sensor::CameraFromFov(640, 480, 40, 0.05, 2.0));
}

std::vector<PlacedPart> LyingParts(const std::vector<std::pair<FixturePart, size_t>>& counts, double floor_side,
                                   uint64_t seed) {
  constexpr double kGap = 0.005;
  std::mt19937_64 bits(seed);
  const auto uniform = [&] { return static_cast<double>(bits() >> 11) * 0x1.0p-53; };
  std::vector<PlacedPart> placed;
  std::vector<Footprint> footprints;
  for (const auto& [part, count] : counts) {
    const TriangleMesh& mesh = *LoadPart(part);
    const std::vector<Eigen::Vector3d> down_axes = DownAxes(part);
    for (size_t n = 0; n < count; ++n) {
      for (int attempt = 0; attempt < 1000; ++attempt) {
        const Eigen::Vector3d down = down_axes[static_cast<size_t>(uniform() * static_cast<double>(down_axes.size()))];
        const Eigen::Matrix3d lying = Eigen::Quaterniond::FromTwoVectors(down, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
        for (const auto& v : mesh.vertices) {
          const Eigen::Vector3d r = lying * v.cast<double>();
          lo = lo.cwiseMin(r);
          hi = hi.cwiseMax(r);
        }
        const double yaw = 2 * kPi * uniform();
        Footprint footprint;
        footprint.axes = {Eigen::Vector2d(std::cos(yaw), std::sin(yaw)), Eigen::Vector2d(-std::sin(yaw), std::cos(yaw))};
        footprint.half = 0.5 * (hi - lo).head<2>();
        const double limit = 0.4 * floor_side;
        footprint.centre = Eigen::Vector2d((2 * uniform() - 1) * limit, (2 * uniform() - 1) * limit);
        const bool inside = footprint.Reach(Eigen::Vector2d::UnitX()) + std::abs(footprint.centre.x()) <= limit &&
                            footprint.Reach(Eigen::Vector2d::UnitY()) + std::abs(footprint.centre.y()) <= limit;
        if (!inside || std::any_of(footprints.begin(), footprints.end(),
                                   [&](const Footprint& f) { return Overlap(f, footprint, kGap); })) {
          continue;
        }
        // Lay the part down, centre its bounding box on the origin with its lowest point at z = 0,
        // turn it about z and move it to its place.
        Pose3 down_pose = Pose3::Identity();
        down_pose.linear() = lying;
        down_pose.translation() = -Eigen::Vector3d(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), lo.z());
        Pose3 place = Pose3::Identity();
        place.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        place.translation() = Eigen::Vector3d(footprint.centre.x(), footprint.centre.y(), 0);
        placed.push_back({part, place * down_pose});
        footprints.push_back(footprint);
        break;
      }
    }
  }
  return placed;
}

std::vector<raycast::SceneInstance> FloorInstances(const std::vector<PlacedPart>& parts, double floor_side) {
  std::vector<raycast::SceneInstance> instances;
  for (size_t i = 0; i < parts.size(); ++i) {
    instances.push_back({LoadPart(parts[i].part), parts[i].world_from_part, 1.0, static_cast<uint32_t>(i + 1)});
  }
  instances.push_back({Square(floor_side), Pose3::Identity(), 1.0, 0});
  return instances;
}

Pose3 FloorSensorPose(double floor_side) { return LookingAtOrigin(floor_side * Eigen::Vector3d(0.1, -0.35, 1.45)); }

PointCloud ScanFloor(const std::vector<PlacedPart>& parts, double floor_side, uint32_t width, uint32_t height) {
  return Cast(FloorInstances(parts, floor_side), FloorSensorPose(floor_side),
              sensor::CameraFromFov(width, height, 50, 0.05, 4 * floor_side));
}

PinsBesideBlocks ScanPinsBesideBlocks() {
  PinsBesideBlocks scene;
  auto pin = std::make_shared<TriangleMesh>(*LoadPart(FixturePart::kRound));
  for (auto& v : pin->vertices) v *= static_cast<float>(kPinScale);
  scene.pin = pin;
  const double radius = 0.0254 * kPinScale;
  const std::vector<PlacedPart> blocks = LyingParts({{FixturePart::kAngleBlock, 6}}, 0.2, 4);
  std::vector<raycast::SceneInstance> instances = FloorInstances(blocks, kPinFloor);
  for (const PlacedPart& block : blocks) scene.blocks.push_back(block.world_from_part);
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(-0.12, 0.125), Eigen::Vector2d(0.03, 0.125),
                                    Eigen::Vector2d(-0.04, -0.13)}) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(at.x(), at.y(), radius);
    scene.pins.push_back(pose);
    instances.push_back({pin, pose, 1.0, static_cast<uint32_t>(100 + scene.pins.size())});
  }
  scene.scan = Cast(instances, FloorSensorPose(kPinFloor), sensor::CameraFromFov(1280, 960, 50, 0.05, 4 * kPinFloor));
  return scene;
}

PartSymmetries PinSymmetries() {
  PartSymmetries symmetries = SymmetriesOf(FixturePart::kRound);
  for (Pose3& flip : symmetries.discrete) flip.translation() *= kPinScale;
  for (auto& axis : symmetries.continuous) axis.point *= kPinScale;
  return symmetries;
}

}  // namespace vscan::localization::testing
