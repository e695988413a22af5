#include "reconstruction/range_image.h"

#include <gtest/gtest.h>

#include "scan_views.h"

namespace vscan::reconstruction {
namespace {

// A plane facing the camera at depth 2: every pixel's depth is 2, whatever the pose.
TEST(RangeImage, RebuiltFromAWorldFrameScan) {
  const Eigen::Vector3d eye(0.3, -0.2, 1.0), target(0.1, 0.4, 0.2);
  const Eigen::Vector3d forward = (target - eye).normalized();
  const auto scene = test::SceneOf(vscan::test::MakeSquare(eye + 2.0 * forward, forward, 10.0));
  const sensor::PinholeCamera camera = sensor::CameraFromFov(40, 30, 50.0, 0.1, 10.0);
  const RangeImage image = test::ScanView(*scene, camera, eye, target);
  ASSERT_EQ(image.depth.size(), camera.pixel_count());
  for (float d : image.depth) EXPECT_NEAR(d, 2.0f, 1e-5f);
  EXPECT_TRUE(ValidateRangeImage(image, "image").ok());
}

TEST(RangeImage, EmptyPixelsAreZeroAndSensorFrameIsTakenAsIs) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(4, 3, 60.0, 0.1, 10.0);
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldPixel;
  cloud.positions = {{0, 0, 1.5f}, {0.1f, 0, 2.5f}};
  cloud.pixels = {5, 11};
  auto image = RangeImageFromScan(cloud, camera, Pose3::Identity(), CloudFrame::kSensor);
  ASSERT_TRUE(image.ok());
  for (size_t i = 0; i < image->depth.size(); ++i) {
    EXPECT_EQ(image->depth[i], i == 5 ? 1.5f : i == 11 ? 2.5f : 0.0f) << i;
  }
}

TEST(RangeImage, NeedsPixelsInsideTheImage) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(4, 3, 60.0, 0.1, 10.0);
  PointCloud cloud;
  cloud.positions = {{0, 0, 1}};
  auto no_pixels = RangeImageFromScan(cloud, camera, Pose3::Identity());
  ASSERT_FALSE(no_pixels.ok());
  EXPECT_NE(no_pixels.status().message().find("cloud"), std::string::npos);
  cloud.fields |= kFieldPixel;
  cloud.pixels = {12};
  EXPECT_FALSE(RangeImageFromScan(cloud, camera, Pose3::Identity()).ok());
  RangeImage short_depth{camera, Pose3::Identity(), std::vector<float>(11)};
  const Status s = ValidateRangeImage(short_depth, "images[0]");
  EXPECT_NE(s.message().find("images[0].depth"), std::string::npos);
}

}  // namespace
}  // namespace vscan::reconstruction
