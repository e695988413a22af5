#include "evaluation/thinned_camera.h"

#include <gtest/gtest.h>

namespace vscan::evaluation {
namespace {

TEST(ThinnedCamera, BudgetStrideIsTheSmallestThatFits) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(1280, 1024, 60, 0.1, 5);
  // 640 x 512 = 327680 rays is over the budget; 426 x 341 = 145266 is within it.
  EXPECT_EQ(BudgetStride(camera, 200'000), 3u);
  EXPECT_EQ(ThinnedPixelCount(camera, 3), 426u * 341u);
  EXPECT_EQ(BudgetStride(camera, camera.pixel_count()), 1u);
  for (const uint64_t budget : {1ull, 7ull, 1000ull, 65'536ull, 500'000ull}) {
    const uint32_t stride = BudgetStride(camera, budget);
    EXPECT_LE(ThinnedPixelCount(camera, stride), budget) << budget;
    if (stride > 1) {
      EXPECT_GT(ThinnedPixelCount(camera, stride - 1), budget) << budget;
    }
  }
}

TEST(ThinnedCamera, RaysPassThroughTheCentresOfTheirBlocks) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(1280, 1024, 60, 0.1, 5);
  const sensor::PinholeCamera thin = ThinCamera(camera, 4);
  EXPECT_EQ(thin.width, 320u);
  EXPECT_EQ(thin.height, 256u);
  EXPECT_EQ(thin.near, camera.near);
  EXPECT_EQ(thin.far, camera.far);
  // A 4 x 4 block's centre is the midpoint of the centres of its two middle pixels.
  for (const auto& [u, v] : {std::pair{0u, 0u}, std::pair{17u, 200u}, std::pair{319u, 255u}}) {
    const Eigen::Vector3f expected =
        (camera.RayThroughPixel(4 * u + 1, 4 * v + 1) + camera.RayThroughPixel(4 * u + 2, 4 * v + 2)) / 2;
    EXPECT_TRUE(thin.RayThroughPixel(u, v).isApprox(expected, 1e-6f)) << u << " " << v;
  }
}

TEST(ThinnedCamera, SpacingStrideKeepsRaysWithinTheSpacing) {
  sensor::PinholeCamera camera = sensor::CameraFromFov(1000, 800, 60, 0.1, 5);
  camera.fx = camera.fy = 1000;
  // One pixel spans 2 mm at 2 m: 5 pixels make 1 cm.
  EXPECT_EQ(SpacingStride(camera, 0.01, 2.0), 5u);
  EXPECT_EQ(SpacingStride(camera, 0.0099, 2.0), 4u);
  EXPECT_EQ(SpacingStride(camera, 0.001, 2.0), 1u);
  EXPECT_EQ(SpacingStride(camera, 100, 2.0), 1000u);
}

}  // namespace
}  // namespace vscan::evaluation
