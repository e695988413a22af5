#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "vscan_test/temp_dir.h"
#include "vscan/render/cloud_colours.h"
#include "vscan/render/colour_map.h"
#include "vscan/render/png_io.h"
#include "vscan/render/renderer.h"

namespace vscan::render {
namespace {

constexpr uint32_t kWidth = 320, kHeight = 240;
constexpr std::array<uint8_t, 3> kBackground = {10, 20, 30};

View FrontView() {
  View view;
  view.eye = {0, 0, 2};
  view.target = {0, 0, 0};
  view.up = {0, 1, 0};
  return view;
}

RenderOptions Options(float point_size = 1) {
  RenderOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.point_size = point_size;
  options.background = kBackground;
  return options;
}

// Pixel coordinates (x right, y down, pixel centres at +0.5) of a point on the plane z = 0 seen by FrontView.
Eigen::Vector2f PixelOf(float x, float y) {
  const float t = std::tan(kVerticalFovDeg * std::numbers::pi_v<float> / 360);
  const float aspect = static_cast<float>(kWidth) / kHeight;
  const float ndc_x = x / (2 * t * aspect), ndc_y = y / (2 * t);
  return {(ndc_x + 1) / 2 * kWidth, (1 - ndc_y) / 2 * kHeight};
}

std::vector<Eigen::Vector3f> Uniform(size_t n, const Eigen::Vector3f& colour) { return {n, colour}; }

StatusOr<Image> Draw(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& colours, const View& view,
                     const RenderOptions& options) {
  return RenderCloud(cloud, colours, test::BoundsOf(cloud.positions), view, options);
}

TEST(RenderCloudTest, SquarePlaneCoversThePredictedRectangleAndNothingElse) {
  // 0.5 m half side seen from 2 m: about 82 pixels half side; 401 samples keep the spacing under a pixel.
  const PointCloud cloud = test::GridCloud(0.5f, 401, [](float u, float v) { return Eigen::Vector3f(u, v, 0); });
  const auto image = Draw(cloud, Uniform(cloud.size(), {1, 0, 0}), FrontView(), Options());
  ASSERT_TRUE(image.ok()) << image.status().message();
  ASSERT_EQ(image->width, kWidth);
  ASSERT_EQ(image->height, kHeight);

  const Eigen::Vector2f low = PixelOf(-0.5f, 0.5f), high = PixelOf(0.5f, -0.5f);
  ASSERT_NEAR(high.x() - low.x(), 164.8f, 0.5f);
  int inside = 0, wrong = 0;
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      const Eigen::Vector2f centre(x + 0.5f, y + 0.5f);
      const bool surely_in = (centre.array() > low.array() + 1).all() && (centre.array() < high.array() - 1).all();
      const bool surely_out = (centre.array() < low.array() - 1).any() || (centre.array() > high.array() + 1).any();
      const auto pixel = image->At(x, y);
      if (surely_in) {
        ++inside;
        wrong += pixel != std::array<uint8_t, 3>{255, 0, 0};
      } else if (surely_out) {
        wrong += pixel != kBackground;
      }
    }
  }
  EXPECT_GT(inside, 160 * 160);
  EXPECT_EQ(wrong, 0);

  // The file holds exactly the rendered pixels.
  vscan::test::TempDir dir;
  const std::string path = (dir.path() / "plane.png").string();
  ASSERT_TRUE(WritePng(*image, path).ok());
  const auto back = ReadPng(path);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->width, kWidth);
  EXPECT_EQ(back->height, kHeight);
  EXPECT_EQ(back->rgb, image->rgb);
}

TEST(RenderCloudTest, DepthColourIncreasesMonotonicallyAlongATiltedPlane) {
  // The top edge leans away from the camera: distance from the eye grows from the bottom row up.
  const PointCloud cloud = test::GridCloud(0.5f, 401, [](float u, float v) { return Eigen::Vector3f(u, v, -v); });
  const View view = FrontView();
  const auto colours = CloudColours(cloud, ColourMode::kDepth, view);
  ASSERT_TRUE(colours.ok());
  const auto image = Draw(cloud, *colours, view, Options());
  ASSERT_TRUE(image.ok()) << image.status().message();

  std::vector<float> along;  // Turbo parameter, bottom row first
  for (int y = kHeight - 1; y >= 0; --y) {
    const auto pixel = image->At(kWidth / 2, static_cast<uint32_t>(y));
    if (pixel != kBackground) along.push_back(test::InverseTurbo(pixel));
  }
  ASSERT_GT(along.size(), 100u);
  for (size_t i = 1; i < along.size(); ++i) {
    EXPECT_GE(along[i], along[i - 1] - 0.01f) << "row " << i << " from the bottom";
  }
  // Nearest point: the bottom edge's middle; farthest: the top corners. The column ends at the top edge's middle.
  const auto distance = [&](float u, float v) { return (Eigen::Vector3f(u, v, -v) - view.eye).norm(); };
  const float top_middle = (distance(0, 0.5f) - distance(0, -0.5f)) / (distance(0.5f, 0.5f) - distance(0, -0.5f));
  EXPECT_NEAR(along.front(), 0.0f, 0.02f);
  EXPECT_NEAR(along.back(), top_middle, 0.02f);
}

TEST(RenderCloudTest, NearerPointsHideFartherOnesWhateverTheDrawOrder) {
  const PointCloud near = test::GridCloud(0.2f, 81, [](float u, float v) { return Eigen::Vector3f(u, v, 0.5f); });
  const PointCloud far = test::GridCloud(0.5f, 201, [](float u, float v) { return Eigen::Vector3f(u, v, -0.5f); });
  for (const bool near_first : {true, false}) {
    const PointCloud& first = near_first ? near : far;
    const PointCloud& second = near_first ? far : near;
    PointCloud both = first;
    both.positions.insert(both.positions.end(), second.positions.begin(), second.positions.end());
    std::vector<Eigen::Vector3f> colours = Uniform(first.size(), near_first ? Eigen::Vector3f(1, 0, 0)
                                                                            : Eigen::Vector3f(0, 0, 1));
    const auto rest = Uniform(second.size(), near_first ? Eigen::Vector3f(0, 0, 1) : Eigen::Vector3f(1, 0, 0));
    colours.insert(colours.end(), rest.begin(), rest.end());
    const auto image = Draw(both, colours, FrontView(), Options(2));
    ASSERT_TRUE(image.ok()) << image.status().message();
    const std::array<uint8_t, 3> red = {255, 0, 0}, blue = {0, 0, 255};
    EXPECT_EQ(image->At(kWidth / 2, kHeight / 2), red) << "near first: " << near_first;
    // Beside the near square (which spans about 44 pixels each way from the centre at z = 0.5) the far one shows.
    EXPECT_EQ(image->At(kWidth / 2 + 55, kHeight / 2), blue) << "near first: " << near_first;
  }
}

TEST(RenderCloudTest, InstanceIdsGetDistinctColoursAndZeroIsGrey) {
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldInstanceId;
  const std::vector<float> centres = {-0.8f, -0.4f, 0.0f, 0.4f, 0.8f};
  for (uint32_t id = 0; id < centres.size(); ++id) {
    const PointCloud patch = test::GridCloud(0.1f, 41, [&](float u, float v) {
      return Eigen::Vector3f(centres[id] + u, v, 0);
    });
    cloud.positions.insert(cloud.positions.end(), patch.positions.begin(), patch.positions.end());
    cloud.instance_ids.insert(cloud.instance_ids.end(), patch.size(), id);
  }
  const auto colours = CloudColours(cloud, ColourMode::kInstance, FrontView());
  ASSERT_TRUE(colours.ok());
  const auto image = Draw(cloud, *colours, FrontView(), Options());
  ASSERT_TRUE(image.ok()) << image.status().message();

  std::vector<Eigen::Vector3f> seen;
  for (uint32_t id = 0; id < centres.size(); ++id) {
    const Eigen::Vector2f at = PixelOf(centres[id], 0);
    const auto pixel = image->At(static_cast<uint32_t>(at.x()), static_cast<uint32_t>(at.y()));
    const Eigen::Vector3f got(pixel[0], pixel[1], pixel[2]);
    EXPECT_LE((got - InstanceColour(id) * 255).cwiseAbs().maxCoeff(), 1.0f) << "id " << id;
    seen.push_back(got);
  }
  EXPECT_LE((seen[0] - Eigen::Vector3f::Constant(127.5f)).cwiseAbs().maxCoeff(), 1.0f);
  for (size_t a = 0; a < seen.size(); ++a) {
    for (size_t b = a + 1; b < seen.size(); ++b) EXPECT_GT((seen[a] - seen[b]).norm(), 40.0f) << a << " vs " << b;
  }
}

TEST(RenderCloudTest, WideSplatsAreRoundDiscsOfTheGivenDiameter) {
  PointCloud cloud;
  cloud.positions = {{0, 0, 0}, {0.5f, 0.3f, 0.2f}};
  const float diameter = 21;
  const auto image = Draw(cloud, Uniform(2, {0, 1, 0}), FrontView(), Options(diameter));
  ASSERT_TRUE(image.ok()) << image.status().message();
  int covered = 0;
  for (uint32_t y = 0; y < kHeight / 2 + 20; ++y) {
    for (uint32_t x = kWidth / 2 - 20; x < kWidth / 2 + 20; ++x) covered += image->At(x, y) != kBackground;
  }
  const float disc = std::numbers::pi_v<float> * diameter * diameter / 4;
  EXPECT_NEAR(covered, disc, 0.08f * disc);
}

TEST(RenderCloudTest, RejectsSizesTheContextCannotDraw) {
  PointCloud cloud;
  cloud.positions = {{0, 0, 0}};
  RenderOptions options = Options(100000);
  const auto too_big_point = Draw(cloud, Uniform(1, {1, 1, 1}), FrontView(), options);
  EXPECT_EQ(too_big_point.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(too_big_point.status().message().rfind("--point-size", 0), 0u) << too_big_point.status().message();
  options = Options();
  options.width = 1 << 20;
  const auto too_wide = Draw(cloud, Uniform(1, {1, 1, 1}), FrontView(), options);
  EXPECT_EQ(too_wide.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(too_wide.status().message().rfind("--width", 0), 0u) << too_wide.status().message();
}

}  // namespace
}  // namespace vscan::render
