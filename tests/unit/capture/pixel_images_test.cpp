#include "capture/pixel_images.h"

#include <gtest/gtest.h>

namespace vscan::capture {
namespace {

PointCloud RaysAt(const std::vector<uint32_t>& pixels, const std::vector<PointStatus>& statuses,
                  const std::vector<float>& intensities) {
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldPixel | kFieldStatus | kFieldIntensity | kFieldRange;
  cloud.Resize(pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) {
    cloud.positions[i] = Eigen::Vector3f(static_cast<float>(i), 0, 1);
    cloud.ranges[i] = static_cast<float>(i);
    cloud.pixels[i] = pixels[i];
    cloud.statuses[i] = static_cast<uint8_t>(statuses[i]);
    cloud.intensities[i] = intensities[i];
  }
  return cloud;
}

TEST(PixelImages, EachPixelTakesItsRaysStatusAndSignalAndTheRestStayZero) {
  const PointCloud cloud = RaysAt({0, 5, 7, 11, 99},
                                  {PointStatus::kMeasured, PointStatus::kRejectedDark, PointStatus::kRejectedSaturated,
                                   PointStatus::kFlyingPixel, PointStatus::kMeasured},
                                  {5000, 10, 10000, 2500, 1});
  const PixelImages images = MakePixelImages(cloud, 4, 3, 10000);
  ASSERT_EQ(images.reasons.size(), 12u);
  ASSERT_EQ(images.gray.size(), 12u);
  const std::vector<uint8_t> reasons{1, 0, 0, 0, 0, 9, 0, 10, 0, 0, 0, 3};
  EXPECT_EQ(images.reasons, reasons);
  EXPECT_EQ(images.gray[0], 32768);  // half the full well: round(32767.5)
  EXPECT_EQ(images.gray[5], 66);     // 10 / 10000 x 65535 = 65.5
  EXPECT_EQ(images.gray[7], 65535);
  EXPECT_EQ(images.gray[11], 16384);
  for (const size_t empty : {1, 2, 3, 4, 6, 8, 9, 10}) EXPECT_EQ(images.gray[empty], 0) << empty;
}

TEST(PixelImages, SignalsPastFullScaleClipAndNegativeOrNanOnesAreBlack) {
  const PointCloud cloud = RaysAt({0, 1, 2}, {PointStatus::kMeasured, PointStatus::kMeasured, PointStatus::kMeasured},
                                  {3.0f, -1.0f, std::numeric_limits<float>::quiet_NaN()});
  const PixelImages images = MakePixelImages(cloud, 3, 1, 1.0);
  EXPECT_EQ(images.gray, (std::vector<uint16_t>{65535, 0, 0}));
}

TEST(PixelImages, DroppingTheRejectedKeepsTheReturnedRaysInOrderWithTheirFields) {
  PointCloud cloud = RaysAt({0, 1, 2, 3, 4},
                            {PointStatus::kRejectedOutOfRange, PointStatus::kMeasured, PointStatus::kRejectedDark,
                             PointStatus::kOutlier, PointStatus::kFlyingPixel},
                            {0, 1, 2, 3, 4});
  DropRejected(cloud);
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_EQ(cloud.pixels, (std::vector<uint32_t>{1, 3, 4}));
  EXPECT_EQ(cloud.intensities, (std::vector<float>{1, 3, 4}));
  EXPECT_EQ(cloud.ranges, (std::vector<float>{1, 3, 4}));
  EXPECT_EQ(cloud.statuses.size(), 3u);
  EXPECT_EQ(cloud.positions[2].x(), 4.0f);
}

}  // namespace
}  // namespace vscan::capture
