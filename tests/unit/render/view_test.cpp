#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "vscan/render/view.h"

namespace vscan::render {
namespace {

Eigen::Vector3f Ndc(const Eigen::Matrix4f& clip_from_world, const Eigen::Vector3f& p) {
  const Eigen::Vector4f clip = clip_from_world * p.homogeneous();
  return clip.head<3>() / clip.w();
}

TEST(ViewTest, ObliqueDirectionIsEqualPartsXMinusYAndUp) {
  EXPECT_TRUE(ObliqueDirection({0, 0, 1}).isApprox(Eigen::Vector3f(1, -1, 1).normalized()));
  EXPECT_TRUE(ObliqueDirection({0, 0, 5}).isApprox(Eigen::Vector3f(1, -1, 1).normalized()));
  const Eigen::Vector3f along_x = ObliqueDirection({1, 0, 0});
  EXPECT_NEAR(along_x.norm(), 1.0f, 1e-6f);
  EXPECT_NEAR(along_x.dot(Eigen::Vector3f::UnitX()), 1 / std::sqrt(3.0f), 1e-6f);
}

TEST(ViewTest, FittedViewFramesTheBoxTightly) {
  Bounds bounds;
  bounds.min = {-1, 2, 0};
  bounds.max = {3, 2.5f, 0.7f};
  for (const float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 2.5f}) {
    for (const Eigen::Vector3f& up : {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 1, 0), Eigen::Vector3f(1, 1, 0)}) {
      const View view = FitView(bounds, up, std::nullopt, aspect);
      EXPECT_TRUE(view.target.isApprox(bounds.Centre()));
      EXPECT_TRUE((view.eye - view.target).normalized().isApprox(ObliqueDirection(up), 1e-5f));
      const Eigen::Matrix4f m = ClipFromWorld(view, bounds, aspect);
      float widest = 0;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3f corner((c & 1) ? bounds.max.x() : bounds.min.x(),
                                     (c & 2) ? bounds.max.y() : bounds.min.y(),
                                     (c & 4) ? bounds.max.z() : bounds.min.z());
        const Eigen::Vector3f ndc = Ndc(m, corner);
        EXPECT_GT(ndc.z(), -1) << "corner " << c << " is nearer than the near plane";
        EXPECT_LT(ndc.z(), 1) << "corner " << c << " is beyond the far plane";
        widest = std::max(widest, ndc.head<2>().cwiseAbs().maxCoeff());
      }
      // Every corner is in view and the outermost one sits on the fill margin.
      EXPECT_NEAR(widest, kFitFill, 1e-4f) << "aspect " << aspect << ", up " << up.transpose();
      EXPECT_LT(Ndc(m, view.target).head<2>().norm(), 1e-5f);
    }
  }
}

TEST(ViewTest, FittedViewLooksAtAGivenTarget) {
  Bounds bounds;
  bounds.min = {0, 0, 0};
  bounds.max = {1, 1, 1};
  const Eigen::Vector3f target(1, 1, 0);
  const View view = FitView(bounds, {0, 0, 1}, target, 1.0f);
  EXPECT_EQ(view.target, target);
  const Eigen::Matrix4f m = ClipFromWorld(view, bounds, 1.0f);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3f corner(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    EXPECT_LE(Ndc(m, corner).head<2>().cwiseAbs().maxCoeff(), kFitFill + 1e-5f) << "corner " << c;
  }
}

TEST(ViewTest, ProjectionMatchesThePinholeModel) {
  View view;
  view.eye = {0, 0, 2};
  view.target = {0, 0, 0};
  view.up = {0, 1, 0};
  Bounds bounds;
  bounds.min = {-1, -1, 0};
  bounds.max = {1, 1, 0};
  const float aspect = 2;
  const Eigen::Matrix4f m = ClipFromWorld(view, bounds, aspect);
  const float t = std::tan(kVerticalFovDeg * std::numbers::pi_v<float> / 360);
  const Eigen::Vector3f ndc = Ndc(m, {0.3f, -0.2f, 0});
  EXPECT_NEAR(ndc.x(), 0.3f / (2 * t * aspect), 1e-6f);
  EXPECT_NEAR(ndc.y(), -0.2f / (2 * t), 1e-6f);
  EXPECT_GT(ndc.z(), -1);
  EXPECT_LT(ndc.z(), 1);
}

}  // namespace
}  // namespace vscan::render
