#include "capture_scenes.h"

#include <gtest/gtest.h>

#include "../raycast/test_meshes.h"

namespace vscan::capture::test {
namespace {

raycast::SceneInstance Instance(TriangleMesh mesh, uint32_t id) {
  raycast::SceneInstance instance;
  instance.mesh = vscan::test::Share(std::move(mesh));
  instance.instance_id = id;
  return instance;
}

}  // namespace

raycast::SceneInstance Plane(double z, double half_size) {
  return Instance(vscan::test::MakeSquare({0, 0, z}, {0, 0, -1}, half_size), kPlaneId);
}

raycast::SceneInstance Sphere(const Eigen::Vector3d& centre, double radius) {
  return Instance(vscan::test::MakeIcosphere(centre, radius, 6), kSphereId);
}

raycast::SceneInstance Box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(static_cast<float>(i & 1 ? hi.x() : lo.x()), static_cast<float>(i & 2 ? hi.y() : lo.y()),
                               static_cast<float>(i & 4 ? hi.z() : lo.z()));
  }
  // Two triangles per face (winding does not matter to the scanner).
  const uint32_t faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    mesh.triangles.push_back({f[0], f[1], f[2]});
    mesh.triangles.push_back({f[0], f[2], f[3]});
  }
  return Instance(std::move(mesh), kBoxId);
}

std::shared_ptr<const raycast::RaycastScene> Build(std::vector<raycast::SceneInstance> instances) {
  auto scene = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  return scene.ok() ? *scene : nullptr;
}

sensor::PinholeCamera Camera(uint32_t width, uint32_t height, double hfov_deg, double far) {
  return sensor::CameraFromFov(width, height, hfov_deg, 0.05, far);
}

PointCloud Measure(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                   const MeasurementSpec& spec, MeasureStats* stats) {
  auto cloud = ScanMeasured(scene, camera, Pose3::Identity(), spec, raycast::ScanFrame::kSensor, nullptr, nullptr,
                            stats);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  return cloud.ok() ? std::move(cloud).value() : PointCloud{};
}

}  // namespace vscan::capture::test
