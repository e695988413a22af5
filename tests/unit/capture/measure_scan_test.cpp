#include "capture/measure_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "capture_scenes.h"

namespace vscan::capture {
namespace {

using test::Build;
using test::Code;
using test::kDeg;
using test::TruthSpec;
using test::Camera;
using test::Measure;


const Eigen::Vector3d kCentre(0, 0, 2);
constexpr double kRadius = 0.5;

// Analytic incidence (radians) of the ray through pixel (u, v) on the sphere, or NaN on a miss.
double AnalyticIncidence(const sensor::PinholeCamera& camera, double u, double v) {
  const Eigen::Vector3d d = Eigen::Vector3d((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1).normalized();
  const double b = d.dot(kCentre);
  const double disc = b * b - kCentre.squaredNorm() + kRadius * kRadius;
  if (disc < 0) return std::nan("");
  const Eigen::Vector3d n = ((b - std::sqrt(disc)) * d - kCentre) / kRadius;
  return std::acos(std::clamp(-d.dot(n), -1.0, 1.0));
}


TEST(MeasureScanTest, GrazingRejectsExactlyTheAnalyticRim) {
  const auto scene = Build({test::Sphere(kCentre, kRadius)});
  const auto camera = Camera(320, 320, 32);
  MeasurementSpec spec = TruthSpec();
  spec.grazing_limit_deg = 60;
  spec.include_rejected = true;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  ASSERT_GT(cloud.size(), 10000u);
  size_t checked = 0, grazing = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double u = cloud.pixels[i] % camera.width + 0.5, v = cloud.pixels[i] / camera.width + 0.5;
    // Facets of the icosphere tilt normals by a fraction of a degree; a pixel's neighbours set the margin.
    double lo = 1e9, hi = -1e9;
    for (double du : {-1.0, 0.0, 1.0}) {
      for (double dv : {-1.0, 0.0, 1.0}) {
        const double a = AnalyticIncidence(camera, u + du, v + dv);
        lo = std::min(lo, std::isnan(a) ? 90 * kDeg : a);
        hi = std::max(hi, std::isnan(a) ? 90 * kDeg : a);
      }
    }
    lo -= 0.5 * kDeg;
    hi += 0.5 * kDeg;
    const bool rejected = cloud.statuses[i] == Code(PointStatus::kRejectedGrazing);
    grazing += rejected;
    EXPECT_NEAR(cloud.incidence_angles[i], AnalyticIncidence(camera, u, v), 1.0 * kDeg + (hi - lo));
    if (hi < 60 * kDeg) {
      EXPECT_FALSE(rejected) << "pixel " << cloud.pixels[i];
      ++checked;
    } else if (lo > 60 * kDeg) {
      EXPECT_TRUE(rejected) << "pixel " << cloud.pixels[i];
      ++checked;
    }
  }
  EXPECT_EQ(grazing, stats.rejected_grazing);
  EXPECT_GT(stats.rejected_grazing, 1000u);
  EXPECT_GT(checked, cloud.size() * 9 / 10);
}

TEST(MeasureScanTest, IncludeRejectedGivesEachReasonWhereExpected) {
  // Sphere in range, background plane beyond far; default lighting makes intensity = cos(incidence).
  const auto scene = Build({test::Sphere(kCentre, kRadius), test::Plane(5.0, 20.0)});
  const auto camera = Camera(240, 240, 40, /*far=*/3.0);
  MeasurementSpec spec = TruthSpec();
  spec.grazing_limit_deg = 70;
  spec.noise.min_intensity = 0.5;
  spec.include_rejected = true;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  ASSERT_EQ(cloud.size(), size_t{camera.width} * camera.height);  // every ray hits the plane or the sphere
  size_t counts[9] = {};
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint8_t s = cloud.statuses[i];
    ++counts[s];
    const double inc = cloud.incidence_angles[i];
    if (cloud.instance_ids[i] == test::kPlaneId) {
      EXPECT_EQ(s, Code(PointStatus::kRejectedOutOfRange));
    } else if (inc > 70 * kDeg) {
      EXPECT_EQ(s, Code(PointStatus::kRejectedGrazing));
    } else if (cloud.intensities[i] < 0.5f) {
      EXPECT_EQ(s, Code(PointStatus::kRejectedDim));
    } else {
      EXPECT_EQ(s, Code(PointStatus::kMeasured));
    }
    // Rejected rays come back at their clean positions.
    EXPECT_EQ(cloud.positions[i], cloud.clean_positions[i]);
  }
  EXPECT_GT(counts[Code(PointStatus::kRejectedOutOfRange)], 0u);
  EXPECT_GT(counts[Code(PointStatus::kRejectedGrazing)], 0u);
  EXPECT_GT(counts[Code(PointStatus::kRejectedDim)], 0u);
  EXPECT_GT(counts[Code(PointStatus::kMeasured)], 0u);
  EXPECT_EQ(stats.rejected_out_of_range, counts[Code(PointStatus::kRejectedOutOfRange)]);
  EXPECT_EQ(stats.rejected_grazing, counts[Code(PointStatus::kRejectedGrazing)]);
  EXPECT_EQ(stats.rejected_dim, counts[Code(PointStatus::kRejectedDim)]);
  EXPECT_EQ(stats.points, counts[Code(PointStatus::kMeasured)]);
  EXPECT_EQ(stats.points + stats.rejected() + stats.dropped, stats.hits);

  // Without include_rejected the same scan returns the measured points only, counters unchanged.
  spec.include_rejected = false;
  MeasureStats again;
  const PointCloud measured = Measure(*scene, camera, spec, &again);
  EXPECT_EQ(measured.size(), stats.points);
  EXPECT_EQ(again.rejected(), stats.rejected());
  for (uint8_t s : measured.statuses) EXPECT_EQ(s, Code(PointStatus::kMeasured));
}

TEST(MeasureScanTest, KeepingEveryRayGivesTheSameRowsAsDroppingTheRejected) {
  // With include_rejected nothing is dropped here (every ray is kept, the arrays move into the
  // output); without it the rejected rays are left out. The returned rows must agree bit for bit.
  const auto scene = Build({test::Sphere(kCentre, kRadius), test::Plane(5.0, 20.0)});
  const auto camera = Camera(160, 160, 40, /*far=*/3.0);
  MeasurementSpec spec = TruthSpec();
  spec.fields |= kFieldEstimatedNormal;
  spec.grazing_limit_deg = 70;
  spec.noise.sigma_a = 0.001;
  spec.flying_pixels.enabled = true;
  spec.seed = 8;
  spec.include_rejected = true;
  MeasureStats all_stats, returned_stats;
  const PointCloud all = Measure(*scene, camera, spec, &all_stats);
  ASSERT_EQ(all.size(), all_stats.hits);
  spec.include_rejected = false;
  const PointCloud returned = Measure(*scene, camera, spec, &returned_stats);
  ASSERT_EQ(returned.size(), returned_stats.points);
  ASSERT_GT(all_stats.rejected(), 1000u);
  size_t k = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    if (all.statuses[i] >= Code(PointStatus::kRejectedOutOfRange)) continue;
    ASSERT_LT(k, returned.size());
    EXPECT_EQ(all.positions[i], returned.positions[k]);
    EXPECT_EQ(all.normals[i], returned.normals[k]);
    EXPECT_EQ(all.ranges[i], returned.ranges[k]);
    EXPECT_EQ(all.intensities[i], returned.intensities[k]);
    EXPECT_EQ(all.instance_ids[i], returned.instance_ids[k]);
    EXPECT_EQ(all.pixels[i], returned.pixels[k]);
    EXPECT_EQ(all.clean_positions[i], returned.clean_positions[k]);
    EXPECT_EQ(all.incidence_angles[i], returned.incidence_angles[k]);
    EXPECT_EQ(all.statuses[i], returned.statuses[k]);
    EXPECT_EQ(all.estimated_normals[i], returned.estimated_normals[k]);
    ++k;
  }
  EXPECT_EQ(k, returned.size());
  EXPECT_EQ(all_stats.min_range, returned_stats.min_range);
  EXPECT_EQ(all_stats.max_range, returned_stats.max_range);
}

TEST(MeasureScanTest, CountersAddUpWithEveryArtefact) {
  const auto scene = Build({test::Sphere(kCentre, kRadius), test::Plane(3.0, 1.0)});
  const auto camera = Camera(200, 160, 50, 2.8);
  MeasurementSpec spec = TruthSpec();
  spec.grazing_limit_deg = 75;
  spec.noise.sigma_a = 0.002;
  spec.noise.min_intensity = 0.1;
  spec.outliers = {0.05, 20, 0.01};
  spec.flying_pixels.enabled = true;
  spec.seed = 5;
  MeasureStats stats;
  const PointCloud cloud = Measure(*scene, camera, spec, &stats);
  EXPECT_EQ(cloud.size(), stats.points);
  EXPECT_EQ(stats.points + stats.rejected() + stats.dropped, stats.hits);
  EXPECT_GT(stats.outliers, 0u);
  EXPECT_GT(stats.rejected_out_of_range, 0u);
  size_t outliers = 0;
  for (uint8_t s : cloud.statuses) outliers += s == Code(PointStatus::kOutlier);
  EXPECT_EQ(outliers, stats.outliers);
}

bool SameBits(const PointCloud& a, const PointCloud& b) {
  return a.size() == b.size() &&
         std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(Eigen::Vector3f)) == 0 &&
         a.statuses == b.statuses && a.pixels == b.pixels;
}

TEST(MeasureScanTest, SameSeedSameBitsOtherSeedOtherNoise) {
  const auto scene = Build({test::Sphere(kCentre, kRadius), test::Plane(3.0, 2.0)});
  const auto camera = Camera(160, 120, 50);
  MeasurementSpec spec = TruthSpec();
  spec.noise.sigma_a = 0.001;
  spec.noise.sigma_b = 0.002;
  spec.outliers = {0.02, 10, 0.005};
  spec.flying_pixels.enabled = true;
  spec.distortion.k1 = 0.05;
  spec.seed = 42;
  const PointCloud a = Measure(*scene, camera, spec);
  const PointCloud b = Measure(*scene, camera, spec);
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(SameBits(a, b));
  spec.seed = 43;
  const PointCloud c = Measure(*scene, camera, spec);
  EXPECT_FALSE(SameBits(a, c));
  size_t differ = 0;
  for (size_t i = 0; i < std::min(a.size(), c.size()); ++i) differ += a.positions[i] != c.positions[i];
  EXPECT_GT(differ, a.size() / 2);
}

TEST(MeasureScanTest, GroundTruthOnlyKeepsTheCleanScan) {
  const auto scene = Build({test::Sphere(kCentre, kRadius)});
  const auto camera = Camera(160, 120, 40);
  const PointCloud cloud = Measure(*scene, camera, TruthSpec());
  raycast::ScanOptions options;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  const auto clean = raycast::Scan(*scene, camera, Pose3::Identity(), options);
  ASSERT_TRUE(clean.ok());
  ASSERT_EQ(cloud.size(), clean->size());
  EXPECT_EQ(cloud.positions, clean->positions);
  EXPECT_EQ(cloud.clean_positions, clean->positions);
  EXPECT_EQ(cloud.normals, clean->normals);
  EXPECT_EQ(cloud.pixels, clean->pixels);
  for (uint8_t s : cloud.statuses) EXPECT_EQ(s, Code(PointStatus::kMeasured));
}

TEST(MeasureScanTest, EstimatedNormalsOfASphereMatchTheAnalyticNormals) {
  const auto scene = Build({test::Sphere(kCentre, kRadius)});
  const auto camera = Camera(320, 320, 32);
  MeasurementSpec spec = TruthSpec();
  spec.fields |= kFieldEstimatedNormal;
  spec.normal_estimation.k = 16;
  const PointCloud cloud = Measure(*scene, camera, spec);
  ASSERT_GT(cloud.size(), 10000u);
  std::vector<double> errors;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.incidence_angles[i] > 70 * kDeg) continue;  // the rim has one-sided neighbourhoods
    const Eigen::Vector3d analytic = (cloud.clean_positions[i].cast<double>() - kCentre).normalized();
    const Eigen::Vector3d estimated = cloud.estimated_normals[i].cast<double>();
    ASSERT_NEAR(estimated.norm(), 1.0, 1e-4);
    EXPECT_LT(estimated.dot(cloud.positions[i].cast<double>()), 0) << "faces the sensor";
    errors.push_back(std::acos(std::clamp(estimated.dot(analytic), -1.0, 1.0)) / kDeg);
  }
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 1.0);
  EXPECT_LT(errors[errors.size() * 99 / 100], 2.0);
}

TEST(MeasureScanTest, RejectedRaysGetZeroEstimatedNormals) {
  const auto scene = Build({test::Sphere(kCentre, kRadius)});
  const auto camera = Camera(160, 160, 32);
  MeasurementSpec spec = TruthSpec();
  spec.fields |= kFieldEstimatedNormal;
  spec.grazing_limit_deg = 50;
  spec.include_rejected = true;
  const PointCloud cloud = Measure(*scene, camera, spec);
  size_t rejected = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.statuses[i] != Code(PointStatus::kRejectedGrazing)) continue;
    ++rejected;
    EXPECT_EQ(cloud.estimated_normals[i], Eigen::Vector3f::Zero());
  }
  EXPECT_GT(rejected, 100u);
}

TEST(MeasureScanTest, OutOfRangeUsesTheDepthLimits) {
  const auto scene = Build({test::Plane(2.0, 5.0)});
  MeasurementSpec spec = TruthSpec();
  spec.include_rejected = true;
  MeasureStats stats;
  const PointCloud beyond = Measure(*scene, Camera(64, 48, 40, /*far=*/1.5), spec, &stats);
  EXPECT_EQ(stats.rejected_out_of_range, 64u * 48u);
  EXPECT_EQ(stats.points, 0u);
  EXPECT_EQ(beyond.size(), 64u * 48u);
  const PointCloud within = Measure(*scene, Camera(64, 48, 40, /*far=*/2.5), spec, &stats);
  EXPECT_EQ(stats.rejected_out_of_range, 0u);
  EXPECT_EQ(within.size(), 64u * 48u);
}

TEST(MeasureScanTest, CancelStopsTheNormalEstimation) {
  const auto scene = Build({test::Sphere(kCentre, kRadius)});
  const auto camera = Camera(160, 160, 32);
  raycast::ScanOptions options;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  auto clean = raycast::Scan(*scene, camera, Pose3::Identity(), options);
  ASSERT_TRUE(clean.ok()) << clean.status().ToString();
  MeasurementSpec spec;
  spec.fields = kFieldsAll | kFieldEstimatedNormal;
  spec.normal_estimation.k = 16;
  const std::atomic<bool> cancelled{true};
  auto cloud = MeasureScan(*scene, camera, Pose3::Identity(), std::move(clean).value(), spec, &cancelled, nullptr);
  ASSERT_FALSE(cloud.ok());
  EXPECT_EQ(cloud.status().code(), StatusCode::kCancelled) << cloud.status().ToString();
}

}  // namespace
}  // namespace vscan::capture
