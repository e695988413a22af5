#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <numbers>

#include "capture/measure_scan.h"
#include "capture_scenes.h"

namespace vscan::capture {
namespace {

using test::Build;
using test::Code;
using test::kDeg;
using test::TruthSpec;
using test::Camera;
using test::Measure;


MeasurementSpec OutlierSpecOf(double rate, double angle_deg, double origin_m) {
  MeasurementSpec spec;
  spec.fields = kFieldsAll | kFieldsGroundTruth;
  spec.outliers = {rate, angle_deg, origin_m};
  spec.seed = 7;
  return spec;
}

TEST(OutlierTest, RateMatchesSpecAndOnlyOutliersMove) {
  const auto scene = Build({test::Plane(2.0, 50.0)});
  const auto camera = Camera(400, 300, 60);
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, OutlierSpecOf(0.1, 5, 0), &stats);
  ASSERT_EQ(cloud.size(), 400u * 300u);  // a tilted ray still meets the large plane
  size_t outliers = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.statuses[i] == Code(PointStatus::kOutlier)) {
      ++outliers;
      EXPECT_NE(cloud.positions[i], cloud.clean_positions[i]);
      EXPECT_NEAR(cloud.positions[i].z(), 2.0f, 1e-4f) << "the perturbed ray's hit is on the plane";
    } else {
      EXPECT_EQ(cloud.statuses[i], Code(PointStatus::kMeasured));
      EXPECT_EQ(cloud.positions[i], cloud.clean_positions[i]);
    }
  }
  const double rate = static_cast<double>(outliers) / static_cast<double>(cloud.size());
  EXPECT_NEAR(rate, 0.1, 0.004);  // ~4 sigma of a binomial over 120k pixels
  EXPECT_EQ(outliers, stats.outliers);
}

TEST(OutlierTest, TiltStaysWithinTheCone) {
  const auto scene = Build({test::Plane(2.0, 50.0)});
  const auto camera = Camera(200, 150, 60);
  const PointCloud cloud = Measure(*scene, camera, OutlierSpecOf(0.3, 10, 0), nullptr);
  double largest = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.statuses[i] != Code(PointStatus::kOutlier)) continue;
    const double c = cloud.positions[i].normalized().dot(cloud.clean_positions[i].normalized());
    largest = std::max(largest, std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi);
  }
  EXPECT_LT(largest, 10.01);
  EXPECT_GT(largest, 8.0);
}

TEST(OutlierTest, TiltIsUniformOverTheConesSolidAngle) {
  // Uniform in solid angle, a tilt below half the cone's angle has probability
  // (1 - cos 10) / (1 - cos 20) = 0.252; uniform in angle it would be 0.5.
  const auto scene = Build({test::Plane(2.0, 50.0)});
  const PointCloud cloud = Measure(*scene, Camera(200, 150, 60), OutlierSpecOf(1.0, 20, 0), nullptr);
  size_t outliers = 0, within_half = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.statuses[i] != Code(PointStatus::kOutlier)) continue;
    ++outliers;
    const Eigen::Vector3d measured = cloud.positions[i].cast<double>().normalized();
    const double c = measured.dot(cloud.clean_positions[i].cast<double>().normalized());
    within_half += std::acos(std::min(1.0, c)) < 10 * std::numbers::pi / 180;
  }
  ASSERT_GT(outliers, 25000u);
  const double expected = (1 - std::cos(10 * std::numbers::pi / 180)) / (1 - std::cos(20 * std::numbers::pi / 180));
  EXPECT_NEAR(static_cast<double>(within_half) / static_cast<double>(outliers), expected, 0.015);
}

TEST(OutlierTest, OriginOnlyPerturbationStaysOnThePlane) {
  const auto scene = Build({test::Plane(2.0, 50.0)});
  const auto camera = Camera(200, 150, 60);
  const PointCloud cloud = Measure(*scene, camera, OutlierSpecOf(0.2, 0, 0.05), nullptr);
  size_t outliers = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.statuses[i] != Code(PointStatus::kOutlier)) continue;
    ++outliers;
    EXPECT_NEAR(cloud.positions[i].z(), 2.0f, 1e-5f);
    EXPECT_NE(cloud.positions[i], cloud.clean_positions[i]);
    // The ball offset slides along the ray onto the plane: at most 0.05 / cos(ray angle) sideways.
    EXPECT_LE((cloud.positions[i] - cloud.clean_positions[i]).norm(),
              0.05f / cloud.clean_positions[i].normalized().z() + 1e-5f);
  }
  EXPECT_GT(outliers, 4000u);
}

TEST(OutlierTest, MissedRaysAreDroppedAndCounted) {
  // A small plane: rays tilted by up to 60 degrees often miss it.
  const auto scene = Build({test::Plane(2.0, 0.5)});
  const auto camera = Camera(100, 100, 20);
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, OutlierSpecOf(0.5, 60, 0), &stats);
  EXPECT_GT(stats.dropped, 0u);
  EXPECT_EQ(cloud.size(), stats.points);
  EXPECT_EQ(stats.points + stats.dropped, stats.hits);
}

TEST(OutlierTest, HitsOutsideTheDepthRangeAreDropped) {
  // Rays tilted off the sphere reach the wall, beyond far: the sensor cannot report them.
  const auto scene = Build({test::Sphere({0, 0, 2}, 0.5), test::Plane(5.0, 20.0)});
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, Camera(120, 120, 40, /*far=*/3.0), OutlierSpecOf(0.5, 30, 0), &stats);
  EXPECT_GT(stats.outliers, 300u);
  EXPECT_GT(stats.dropped, 300u);
  for (size_t i = 0; i < cloud.size(); ++i) EXPECT_LE(cloud.positions[i].z(), 3.0f) << "pixel " << cloud.pixels[i];
  EXPECT_EQ(stats.points + stats.rejected() + stats.dropped, stats.hits);
}

TEST(FlyingPixelTest, OnlyAtTheBoxEdgeAndBetweenTheDepths) {
  // Box front face at depth 1, plane behind at depth 2.
  const auto scene = Build({test::Plane(2.0, 5.0), test::Box({-0.2, -0.2, 1.0}, {0.2, 0.2, 1.4})});
  const auto camera = Camera(200, 200, 40);
  MeasurementSpec spec;
  spec.fields = kFieldsAll | kFieldsGroundTruth;
  spec.flying_pixels.enabled = true;
  spec.seed = 3;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  ASSERT_EQ(cloud.size(), 200u * 200u);
  std::vector<float> depth(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) depth[cloud.pixels[i]] = cloud.clean_positions[i].z();
  size_t flying = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t p = cloud.pixels[i], u = p % 200, v = p / 200;
    const bool at_edge = depth[p] < 1.5f && ((u > 0 && depth[p - 1] > 1.5f) || (u < 199 && depth[p + 1] > 1.5f) ||
                                             (v > 0 && depth[p - 200] > 1.5f) || (v < 199 && depth[p + 200] > 1.5f));
    const bool flew = cloud.statuses[i] == Code(PointStatus::kFlyingPixel);
    EXPECT_EQ(flew, at_edge) << "pixel " << u << "," << v;
    if (!flew) {
      EXPECT_EQ(cloud.positions[i], cloud.clean_positions[i]);
      continue;
    }
    ++flying;
    EXPECT_EQ(cloud.instance_ids[i], test::kBoxId);
    EXPECT_GE(cloud.positions[i].z(), 1.0f - 1e-5f);
    EXPECT_LE(cloud.positions[i].z(), 2.0f + 1e-5f);
    // Along the pixel's ray.
    EXPECT_NEAR(cloud.positions[i].normalized().dot(cloud.clean_positions[i].normalized()), 1.0f, 1e-6f);
  }
  EXPECT_EQ(flying, stats.flying_pixels);
  EXPECT_GT(flying, 100u);
}

TEST(MeasurementSpecTest, ValidationNamesTheField) {
  const auto message = [](const MeasurementSpec& spec) {
    return ValidateMeasurementSpec(spec, "noise", "normal_estimation").message();
  };
  MeasurementSpec spec;
  EXPECT_TRUE(ValidateMeasurementSpec(spec, "noise", "normal_estimation").ok());
  spec.outliers = {1.5, 5, 0};
  EXPECT_TRUE(message(spec).starts_with("noise.outlier_rate:")) << message(spec);
  spec.outliers = {0.1, 0, 0};
  EXPECT_TRUE(message(spec).starts_with("noise.outlier_rate:")) << message(spec);
  spec.outliers = {0.1, 90, 0};
  EXPECT_TRUE(message(spec).starts_with("noise.outlier_angle_deg:")) << message(spec);
  spec.outliers = {0.1, 5, -1};
  EXPECT_TRUE(message(spec).starts_with("noise.outlier_origin_m:")) << message(spec);
  spec.outliers = {};
  spec.grazing_limit_deg = std::nan("");
  EXPECT_TRUE(message(spec).starts_with("noise.grazing_limit_deg:")) << message(spec);
  spec.grazing_limit_deg = 0;
  spec.normal_estimation.k = 2;
  EXPECT_TRUE(message(spec).starts_with("normal_estimation.k:")) << message(spec);
}

}  // namespace
}  // namespace vscan::capture
