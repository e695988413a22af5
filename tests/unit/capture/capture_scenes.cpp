#include "capture_scenes.h"

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

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
  return Instance(vscan::test::MakeBox(lo, hi), kBoxId);
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
