// Ground truth of small objects at the image's edges: the object cast alone over a crop of the
// image must give the same count as the object cast alone over the whole image.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "service/scan/scan_ground_truth.h"

namespace vscan::service {
namespace {

// An axis-aligned cube of edge `size` centred on the origin, faces outward.
std::shared_ptr<const TriangleMesh> Cube(float size) {
  auto mesh = std::make_shared<TriangleMesh>();
  const float h = 0.5f * size;
  for (int corner = 0; corner < 8; ++corner) {
    mesh->vertices.emplace_back(corner & 1 ? h : -h, corner & 2 ? h : -h, corner & 4 ? h : -h);
  }
  mesh->triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

scenes::ScanTarget OneObject(const Eigen::Vector3d& position) {
  raycast::SceneInstance instance{Cube(0.004f), Pose3::Identity(), 1.0, 7};
  instance.world_from_object.translation() = position;
  auto instances = std::make_shared<std::vector<raycast::SceneInstance>>(1, instance);
  scenes::ScanTarget target;
  auto built = raycast::RaycastScene::Build(*instances);
  EXPECT_TRUE(built.ok());
  target.raycast = *built;
  target.instances = instances;
  store::ObjectRecord object;
  object.object_id = "obj_cube";
  object.instance_id = 7;
  target.scene.objects.push_back(object);
  return target;
}

// A 4 mm cube 1 m in front of a 1280 x 1024 camera covers about 5 x 5 pixels: at the right edge,
// at the bottom corner, and in the middle.
TEST(ScanGroundTruth, ASmallObjectAtTheImageEdgeCountsAsItDoesOverTheWholeImage) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(1280, 1024, 50, 0.1, 5.0);
  const double edge_x = (1279.0 - camera.cx) / camera.fx, edge_y = (1023.0 - camera.cy) / camera.fy;
  for (const Eigen::Vector3d& position :
       {Eigen::Vector3d(edge_x, 0, 1), Eigen::Vector3d(edge_x, edge_y, 1), Eigen::Vector3d(0, 0, 1),
        Eigen::Vector3d(-(camera.cx - 1.0) / camera.fx, -(camera.cy - 1.0) / camera.fy, 1)}) {
    const scenes::ScanTarget target = OneObject(position);
    raycast::ScanOptions options;
    options.fields = kFieldPosition | kFieldInstanceId | kFieldPixel;
    auto whole = raycast::Scan(*target.raycast, camera, Pose3::Identity(), options);
    ASSERT_TRUE(whole.ok()) << whole.status().ToString();
    ASSERT_GT(whole->size(), 0u) << position.transpose();
    auto truth = ObjectGroundTruth(target, camera, Pose3::Identity(), *whole, nullptr);
    ASSERT_TRUE(truth.ok()) << position.transpose() << ": " << truth.status().ToString();
    ASSERT_EQ(truth->size(), 1u);
    EXPECT_EQ((*truth)[0].unoccluded_points, whole->size()) << position.transpose();
    EXPECT_EQ((*truth)[0].visible_points, whole->size());
    EXPECT_DOUBLE_EQ((*truth)[0].visible_fraction, 1.0);
    EXPECT_LT((*truth)[0].alone_u0, (*truth)[0].alone_u1);
    EXPECT_LE((*truth)[0].alone_u1, camera.width);
    EXPECT_LE((*truth)[0].alone_v1, camera.height);
    // The silhouette from the cropped cast alone is the whole image's pixels of the object.
    std::vector<uint32_t> pixels = whole->pixels;
    std::sort(pixels.begin(), pixels.end());
    EXPECT_EQ((*truth)[0].alone_pixels, pixels) << position.transpose();
  }
}

}  // namespace
}  // namespace vscan::service
