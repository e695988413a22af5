#pragma once
// Range images of a scene from views around a centre, cast with the project's ray caster.

#include <vector>

#include <gtest/gtest.h>

#include "raycast/scanner.h"
#include "reconstruction/range_image.h"
#include "vscan_test/meshes.h"

namespace vscan::reconstruction::test {

inline std::shared_ptr<const raycast::RaycastScene> SceneOf(const TriangleMesh& mesh) {
  raycast::SceneInstance instance;
  instance.mesh = vscan::test::Share(mesh);
  auto scene = raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1));
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  return *scene;
}

inline RangeImage ScanView(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                           const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  const Eigen::Vector3d up = std::abs(forward.z()) > 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  auto pose = PoseFromLookAt(eye, target, up, "test");
  EXPECT_TRUE(pose.ok());
  raycast::ScanOptions options;
  options.fields = kFieldPosition | kFieldPixel;
  auto cloud = raycast::Scan(scene, camera, *pose, options);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  auto image = RangeImageFromScan(*cloud, camera, *pose);
  EXPECT_TRUE(image.ok()) << image.status().ToString();
  return std::move(image).value();
}

// Six views along the axes, each `distance` from centre.
inline std::vector<RangeImage> SixViews(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                        const Eigen::Vector3d& centre, double distance) {
  std::vector<RangeImage> images;
  for (int a = 0; a < 3; ++a) {
    for (double sign : {1.0, -1.0}) {
      images.push_back(ScanView(scene, camera, centre + sign * distance * Eigen::Vector3d::Unit(a), centre));
    }
  }
  return images;
}

}  // namespace vscan::reconstruction::test
