#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "vscan_test/meshes.h"
#include "vscan/render/renderer.h"

namespace vscan::render {
namespace {

constexpr uint32_t kSide = 256;

TEST(RenderMeshTest, HeadlitSphereIsBrightestAtTheCentreAndDarkensOutwards) {
  const float radius = 0.5f, distance = 3;
  const TriangleMesh sphere = vscan::test::MakeIcosphere(Eigen::Vector3d::Zero(), radius, 4);
  View view;
  view.eye = {0, 0, distance};
  view.up = {0, 1, 0};
  RenderOptions options;
  options.width = options.height = kSide;
  options.background = {0, 0, 0};
  const auto image = RenderMesh(sphere, test::BoundsOf(sphere.vertices), view, options);
  ASSERT_TRUE(image.ok()) << image.status().message();

  int best = -1;
  for (uint32_t y = 0; y < kSide; ++y) {
    for (uint32_t x = 0; x < kSide; ++x) {
      const auto p = image->At(x, y);
      ASSERT_TRUE(p[0] == p[1] && p[1] == p[2]) << "the mesh is drawn in grey";
      best = std::max(best, static_cast<int>(p[0]));
    }
  }
  EXPECT_NEAR(best, kMeshGrey * 255, 2.0);
  // The cosine is flat near its peak, so the brightest few levels form a small disc: its centre is the
  // point facing the eye, which projects to the image centre.
  double sum_x = 0, sum_y = 0;
  int brightest = 0;
  for (uint32_t y = 0; y < kSide; ++y) {
    for (uint32_t x = 0; x < kSide; ++x) {
      if (image->At(x, y)[0] + 2 < best) continue;
      sum_x += x + 0.5;
      sum_y += y + 0.5;
      ++brightest;
    }
  }
  ASSERT_GT(brightest, 0);
  EXPECT_LE(std::hypot(sum_x / brightest - kSide / 2.0, sum_y / brightest - kSide / 2.0), 1.5);
  EXPECT_LT(brightest, 1000) << "the brightest levels should be a small disc, not the whole sphere";

  // The silhouette: the cone from the eye touching the sphere.
  const float tan_half = std::tan(kVerticalFovDeg * std::numbers::pi_v<float> / 360);
  const float silhouette = std::tan(std::asin(radius / distance)) / tan_half * kSide / 2;
  const uint32_t row = kSide / 2;
  int previous = 256, lit = 0;
  for (uint32_t x = kSide / 2; x < kSide; ++x) {
    const int v = image->At(x, row)[0];
    if (v == 0) break;
    EXPECT_LE(v, previous + 1) << "x = " << x;
    previous = v;
    ++lit;
  }
  EXPECT_NEAR(lit, silhouette, 2.0f);
  // Near the rim the surface turns away from the light: Lambert falls towards the ambient term.
  const int rim = image->At(kSide / 2 + static_cast<uint32_t>(silhouette * 0.97f), row)[0];
  EXPECT_LT(rim, best / 2);
  EXPECT_GT(rim, static_cast<int>(kMeshAmbient * kMeshGrey * 255) - 2);
}

}  // namespace
}  // namespace vscan::render
