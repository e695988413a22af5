#include "machined_parts.h"

#include <cmath>
#include <numbers>
#include <random>
#include <utility>

#include "raycast/scanner.h"
#include "sensor/camera.h"

namespace vscan::registration::testing {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

uint32_t AddVertex(TriangleMesh& mesh, float x, float y, float z) {
  mesh.vertices.emplace_back(x, y, z);
  return static_cast<uint32_t>(mesh.vertices.size() - 1);
}

// A closed prism over the polygon (counter-clockwise seen from +z) between heights z0 and z1.
void AddPrism(TriangleMesh& mesh, const std::vector<Eigen::Vector2f>& polygon, float z0, float z1) {
  const auto n = static_cast<uint32_t>(polygon.size());
  const uint32_t base = static_cast<uint32_t>(mesh.vertices.size());
  for (const auto& p : polygon) AddVertex(mesh, p.x(), p.y(), z0);
  for (const auto& p : polygon) AddVertex(mesh, p.x(), p.y(), z1);
  for (uint32_t i = 1; i + 1 < n; ++i) {
    mesh.triangles.push_back({base, base + i + 1, base + i});
    mesh.triangles.push_back({base + n, base + n + i, base + n + i + 1});
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({base + i, base + j, base + n + j});
    mesh.triangles.push_back({base + i, base + n + j, base + n + i});
  }
}

void AddBox(TriangleMesh& mesh, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  AddPrism(mesh, {{lo.x(), lo.y()}, {hi.x(), lo.y()}, {hi.x(), hi.y()}, {lo.x(), hi.y()}}, lo.z(), hi.z());
}

TriangleMesh Bracket() {
  TriangleMesh mesh;
  AddBox(mesh, {-0.08f, -0.05f, -0.03f}, {0.08f, 0.05f, -0.015f});   // base plate
  AddBox(mesh, {-0.08f, 0.03f, -0.015f}, {0.02f, 0.05f, 0.05f});     // riser
  AddBox(mesh, {0.035f, -0.035f, -0.015f}, {0.06f, -0.01f, 0.005f}); // boss
  AddBox(mesh, {-0.06f, -0.04f, -0.015f}, {-0.045f, -0.025f, 0.0f}); // small boss
  AddBox(mesh, {-0.02f, -0.03f, -0.015f}, {0.01f, 0.0f, -0.005f});   // low pad
  AddBox(mesh, {0.02f, 0.03f, -0.015f}, {0.05f, 0.045f, 0.02f});     // rib beside the riser
  return mesh;
}

TriangleMesh SteppedBlock() {
  TriangleMesh mesh;
  AddBox(mesh, {-0.07f, -0.05f, -0.04f}, {0.07f, 0.05f, -0.01f});
  AddBox(mesh, {-0.07f, -0.05f, -0.01f}, {0.03f, 0.05f, 0.015f});
  AddBox(mesh, {-0.07f, -0.05f, 0.015f}, {-0.015f, 0.02f, 0.04f});
  AddBox(mesh, {0.04f, 0.01f, -0.01f}, {0.06f, 0.035f, 0.01f});
  AddBox(mesh, {-0.005f, -0.04f, 0.015f}, {0.02f, -0.02f, 0.025f});
  return mesh;
}

TriangleMesh SevenSidedPrism() {
  TriangleMesh mesh;
  std::vector<Eigen::Vector2f> polygon;
  const float radii[] = {0.07f, 0.06f, 0.075f, 0.055f, 0.065f, 0.08f, 0.06f};
  for (int i = 0; i < 7; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 7.0;
    polygon.emplace_back(radii[i] * static_cast<float>(std::cos(a)), radii[i] * static_cast<float>(std::sin(a)));
  }
  AddPrism(mesh, polygon, -0.03f, 0.02f);
  AddBox(mesh, {-0.02f, -0.015f, 0.02f}, {0.025f, 0.02f, 0.04f});
  AddBox(mesh, {0.03f, 0.01f, 0.02f}, {0.045f, 0.03f, 0.03f});
  return mesh;
}

}  // namespace

MachinedPart MakeMachinedPart(int which) {
  MachinedPart part;
  switch (which) {
    case 0: part = {"bracket", Bracket(), nullptr}; break;
    case 1: part = {"stepped block", SteppedBlock(), nullptr}; break;
    default: part = {"seven-sided prism", SevenSidedPrism(), nullptr}; break;
  }
  const raycast::SceneInstance instance{std::make_shared<const TriangleMesh>(part.mesh)};
  part.scene = raycast::RaycastScene::Build(std::span(&instance, 1)).value();
  return part;
}

Pose3 ViewOfPart(double azimuth_deg, double elevation_deg, double distance) {
  const double a = azimuth_deg * kRadiansPerDegree, e = elevation_deg * kRadiansPerDegree;
  const Eigen::Vector3d eye = distance * Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
  return PoseFromLookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), "view").value();
}

std::vector<Eigen::Vector3f> ScanPart(const MachinedPart& part, const Pose3& world_from_sensor, double noise_sigma,
                                      uint32_t seed, const PartCamera& view) {
  raycast::ScanOptions options;
  options.fields = kFieldPosition;
  options.frame = raycast::ScanFrame::kSensor;
  const auto camera = sensor::CameraFromFov(view.width, view.height, view.fov_deg, 0.05, 2.0);
  std::vector<Eigen::Vector3f> points = raycast::Scan(*part.scene, camera, world_from_sensor, options).value().positions;
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_sigma));
  for (auto& p : points) p += Eigen::Vector3f(noise(rng), noise(rng), noise(rng));
  return points;
}

}  // namespace vscan::registration::testing
