#include "evaluation/coverage_image.h"

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluation/surface_sampling.h"
#include "vscan/common/png_codec.h"
#include "vscan_test/meshes.h"

namespace vscan::evaluation {
namespace {

constexpr int kPanel = 200;
constexpr float kCoverageRadius = 0.1f;

std::vector<Eigen::Vector3f> SphereSamples() {
  return SampleSurface(test::MakeIcosphere(Eigen::Vector3d::Zero(), kCoverageRadius, 4), 80'000, 21);
}

RgbPixels Render(std::span<const Eigen::Vector3f> samples, std::span<const uint8_t> covered) {
  CoverageImageOptions options;
  options.panel_size = kPanel;
  const auto png = RenderCoveragePng(samples, covered, options);
  EXPECT_TRUE(png.ok()) << png.status().ToString();
  auto pixels = DecodePng(*png);
  EXPECT_TRUE(pixels.ok()) << pixels.status().ToString();
  return std::move(pixels).value();
}

std::array<uint8_t, 3> At(const RgbPixels& image, int x, int y) {
  const size_t at = (size_t(y) * image.width + size_t(x)) * 3;
  return {image.rgb[at], image.rgb[at + 1], image.rgb[at + 2]};
}

bool IsRed(const std::array<uint8_t, 3>& c) { return c[0] > 150 && c[1] < 80 && c[2] < 80; }
bool IsGrey(const std::array<uint8_t, 3>& c) { return c[0] == c[1] && c[1] == c[2] && c[0] < 255; }

// Counts of red and grey pixels in panel k (0 front, 1 right, 2 back, 3 left).
std::pair<size_t, size_t> RedAndGrey(const RgbPixels& image, int k) {
  size_t red = 0, grey = 0;
  for (int y = 0; y < kPanel; ++y) {
    for (int x = 0; x < kPanel; ++x) {
      const auto c = At(image, (k % 2) * kPanel + x, (k / 2) * kPanel + y);
      red += IsRed(c) ? 1 : 0;
      grey += IsGrey(c) ? 1 : 0;
    }
  }
  return {red, grey};
}

uint32_t BigEndian(const std::string& bytes, size_t at) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<uint8_t>(bytes[at + i]);
  return v;
}

TEST(CoverageImage, IsAPngOfTwoByTwoPanels) {
  const std::vector<Eigen::Vector3f> samples = SphereSamples();
  const std::vector<uint8_t> covered(samples.size(), 1);
  CoverageImageOptions options;
  options.panel_size = 150;
  const auto png = RenderCoveragePng(samples, covered, options);
  ASSERT_TRUE(png.ok()) << png.status().ToString();
  // The signature, then the IHDR chunk: length, type, width and height.
  ASSERT_GT(png->size(), 24u);
  EXPECT_EQ(png->substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png->substr(12, 4), "IHDR");
  EXPECT_EQ(BigEndian(*png, 16), 300u);
  EXPECT_EQ(BigEndian(*png, 20), 300u);
}

TEST(CoverageImage, AllCoveredHasNoRed) {
  const std::vector<Eigen::Vector3f> samples = SphereSamples();
  const RgbPixels image = Render(samples, std::vector<uint8_t>(samples.size(), 1));
  ASSERT_EQ(image.width, 2u * kPanel);
  ASSERT_EQ(image.height, 2u * kPanel);
  for (int k = 0; k < 4; ++k) {
    const auto [red, grey] = RedAndGrey(image, k);
    EXPECT_EQ(red, 0u) << k;
    // The sphere's disc: pi (0.9 * 100 px)^2 is about 25400 pixels.
    EXPECT_NEAR(static_cast<double>(grey), 25'400, 1'500) << k;
  }
  EXPECT_EQ(At(image, 2, 2), (std::array<uint8_t, 3>{255, 255, 255}));
}

TEST(CoverageImage, MissedHalfIsRedWhereItFacesTheViewer) {
  // With z up, the front panel looks along +y: the covered half (y < 0) faces it, the missed half
  // faces the back panel, and the side panels show half of each.
  const std::vector<Eigen::Vector3f> samples = SphereSamples();
  std::vector<uint8_t> covered;
  for (const Eigen::Vector3f& p : samples) covered.push_back(p.y() < 0 ? 1 : 0);
  const RgbPixels image = Render(samples, covered);
  const auto [front_red, front_grey] = RedAndGrey(image, 0);
  const auto [right_red, right_grey] = RedAndGrey(image, 1);
  const auto [back_red, back_grey] = RedAndGrey(image, 2);
  const auto [left_red, left_grey] = RedAndGrey(image, 3);
  EXPECT_GT(back_red, 20'000u);
  EXPECT_LT(front_red, back_red / 50);
  EXPECT_GT(front_grey, 20'000u);
  EXPECT_LT(back_grey, front_grey / 50);
  EXPECT_NEAR(static_cast<double>(right_red), static_cast<double>(right_grey), 2'000);
  EXPECT_NEAR(static_cast<double>(left_red), static_cast<double>(left_grey), 2'000);
  // Seen from the right (+x), the front (-y) is on the viewer's left: grey left, red right.
  EXPECT_TRUE(IsGrey(At(image, kPanel + kPanel / 2 - 40, kPanel / 2)));
  EXPECT_TRUE(IsRed(At(image, kPanel + kPanel / 2 + 40, kPanel / 2)));
}

TEST(CoverageImage, NearerIsLighter) {
  const std::vector<Eigen::Vector3f> samples = SphereSamples();
  const RgbPixels image = Render(samples, std::vector<uint8_t>(samples.size(), 1));
  // The front panel's centre shows the sphere's nearest point (grey 225); 0.9 radii to the side the
  // surface lies 0.44 radii deeper, 28% of the way to the far side: 225 - 0.28 * 155 = 181.
  const auto centre = At(image, kPanel / 2, kPanel / 2);
  const auto side = At(image, kPanel / 2 + 81, kPanel / 2);
  ASSERT_TRUE(IsGrey(centre));
  ASSERT_TRUE(IsGrey(side));
  EXPECT_NEAR(centre[0], 225, 6);
  EXPECT_NEAR(side[0], 181, 10);
}

TEST(CoverageImage, RejectsBadInputs) {
  const std::vector<Eigen::Vector3f> samples = {{0, 0, 0}, {1, 0, 0}};
  const std::vector<uint8_t> covered = {1, 0};
  EXPECT_EQ(RenderCoveragePng(samples, std::vector<uint8_t>{1}).status().field(), "covered");
  CoverageImageOptions options;
  options.panel_size = 0;
  EXPECT_EQ(RenderCoveragePng(samples, covered, options).status().field(), "coverage_image.panel_size");
  options.panel_size = 100'000;
  EXPECT_EQ(RenderCoveragePng(samples, covered, options).status().field(), "coverage_image.panel_size");
  options = {};
  options.up = Eigen::Vector3f::Zero();
  EXPECT_EQ(RenderCoveragePng(samples, covered, options).status().field(), "coverage_image.up");
  const std::vector<Eigen::Vector3f> bad = {{0, 0, 0}, {std::numeric_limits<float>::quiet_NaN(), 0, 0}};
  const auto result = RenderCoveragePng(bad, covered);
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(result.status().field(), "samples[1]");
  // No samples at all is a blank picture.
  const auto blank = RenderCoveragePng({}, {});
  ASSERT_TRUE(blank.ok());
  EXPECT_TRUE(HasPngSignature(*blank));
}

}  // namespace
}  // namespace vscan::evaluation
