// Disparity quantisation: depths snap to the inverse-depth grid of the decoder's disparity step.

#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "sensor/structured_light.h"

namespace vscan::sensor {
namespace {

// Points of the plane n . p = d seen through every pixel of the camera (all in front of it).
std::vector<Eigen::Vector3f> TiltedPlanePoints(const PinholeCamera& camera) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  const double d = 0.9;
  std::vector<Eigen::Vector3f> points;
  for (uint32_t v = 0; v < camera.height; ++v) {
    for (uint32_t u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray = camera.RayThroughPixel(u, v).cast<double>();
      points.push_back((ray * (d / n.dot(ray))).cast<float>());
    }
  }
  return points;
}

StructuredLight DisparityScanner(double step, double convergence) {
  StructuredLight sl;
  sl.camera = CameraFromFov(160, 120, 60.0, 0.1, 5.0);
  sl.projector_offset = {0.08, 0, 0};
  sl.disparity_step_px = step;
  sl.convergence_distance = convergence;
  EXPECT_TRUE(ValidateStructuredLight(sl, "sl").ok());
  return sl;
}

void ExpectOnInverseDepthGrid(const StructuredLight& sl) {
  const std::vector<Eigen::Vector3f> clean = TiltedPlanePoints(sl.camera);
  std::vector<Eigen::Vector3f> quantised = clean;
  QuantiseDisparity(sl, quantised);
  const double fb = sl.camera.fx * 0.08;
  const double inverse_zc = sl.convergence_distance > 0 ? 1.0 / sl.convergence_distance : 0.0;
  const double step = sl.disparity_step_px;
  std::vector<long> levels;
  size_t moved = 0;
  for (size_t i = 0; i < clean.size(); ++i) {
    const Eigen::Vector3d p = clean[i].cast<double>();
    const Eigen::Vector3d q = quantised[i].cast<double>();
    ASSERT_TRUE(q.allFinite());
    // On its own camera ray.
    EXPECT_NEAR(q.x() / q.z(), p.x() / p.z(), 1e-6);
    EXPECT_NEAR(q.y() / q.z(), p.y() / p.z(), 1e-6);
    // 1/z' = 1/z_c + k * step / (f b) for an integer k ...
    const double k = (1.0 / q.z() - inverse_zc) * fb / step;
    EXPECT_NEAR(k, std::round(k), 2e-3) << "depth " << q.z();
    levels.push_back(std::lround(k));
    // ... within half a step of the true disparity: |1/z' - 1/z| <= step / (2 f b).
    EXPECT_LE(std::abs(1.0 / q.z() - 1.0 / p.z()), step / (2 * fb) * (1 + 1e-3) + 1e-6);
    if (std::abs(q.z() - p.z()) > 1e-6) ++moved;
  }
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  // The tilted plane spans several levels, and most points moved.
  EXPECT_GE(levels.size(), 3u);
  EXPECT_GT(moved, clean.size() / 2);
}

TEST(QuantiseDisparity, ParallelAxesSnapToFbOverKStep) { ExpectOnInverseDepthGrid(DisparityScanner(0.5, 0)); }

TEST(QuantiseDisparity, ConvergedAxesMeasureDisparityFromTheConvergencePlane) {
  ExpectOnInverseDepthGrid(DisparityScanner(0.5, 0.8));
}

TEST(QuantiseDisparity, ZeroStepLeavesPointsUnchanged) {
  const StructuredLight sl = DisparityScanner(0, 0.8);
  const std::vector<Eigen::Vector3f> clean = TiltedPlanePoints(sl.camera);
  std::vector<Eigen::Vector3f> points = clean;
  QuantiseDisparity(sl, points);
  EXPECT_EQ(points, clean);
}

TEST(QuantiseDisparity, ConvergencePlaneIsAFixedPoint) {
  // Disparity 0 is on every grid: a point at the convergence depth does not move.
  const StructuredLight sl = DisparityScanner(0.7, 0.8);
  std::vector<Eigen::Vector3f> points{{0.1f, -0.05f, 0.8f}};
  QuantiseDisparity(sl, points);
  EXPECT_NEAR(points[0].z(), 0.8f, 1e-6);
  EXPECT_NEAR(points[0].x(), 0.1f, 1e-6);
}

TEST(QuantiseDisparity, ZeroDisparityWithParallelAxesHasNoDepth) {
  StructuredLight sl = DisparityScanner(1.0, 0);
  sl.projector_offset = {0.01, 0, 0};
  // d = fx * 0.01 / 4 < 0.5 px rounds to 0: infinitely far.
  ASSERT_LT(DisparityAtDepth(sl, 4.0), 0.5);
  std::vector<Eigen::Vector3f> points{{0.2f, 0.1f, 4.0f}};
  QuantiseDisparity(sl, points);
  EXPECT_TRUE(std::isnan(points[0].z()));
}

TEST(Disparity, VerticalBaselineUsesFy) {
  StructuredLight sl = DisparityScanner(0, 0);
  sl.camera.fy = 2 * sl.camera.fx;
  sl.projector_offset = {0, -0.1, 0};
  EXPECT_DOUBLE_EQ(DisparityBaseline(sl), 0.1);
  EXPECT_DOUBLE_EQ(DisparityFocalPx(sl), sl.camera.fy);
  EXPECT_NEAR(DepthAtDisparity(sl, DisparityAtDepth(sl, 1.3)), 1.3, 1e-12);
}

}  // namespace
}  // namespace vscan::sensor
