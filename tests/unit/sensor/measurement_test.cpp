#include "sensor/measurement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "sensor/camera.h"

namespace vscan::sensor {
namespace {

constexpr uint32_t kWidth = 400, kHeight = 300;  // 120k points

// A plane at depth z seen through a 60 degree camera, one point per pixel.
PointCloud PlaneCloud(double z, uint32_t fields = kFieldPosition | kFieldRange | kFieldPixel) {
  const PinholeCamera camera = CameraFromFov(kWidth, kHeight, 60.0, 0.05, 100.0);
  PointCloud cloud;
  cloud.fields = fields;
  cloud.Resize(uint64_t{kWidth} * kHeight);
  for (uint32_t v = 0; v < kHeight; ++v) {
    for (uint32_t u = 0; u < kWidth; ++u) {
      const uint32_t i = v * kWidth + u;
      cloud.positions[i] = camera.RayThroughPixel(u, v) * static_cast<float>(z);
      if (cloud.Has(kFieldRange)) cloud.ranges[i] = cloud.positions[i].norm();
      if (cloud.Has(kFieldPixel)) cloud.pixels[i] = i;
      if (cloud.Has(kFieldIntensity)) cloud.intensities[i] = static_cast<float>(i % 10) / 10.0f;
      if (cloud.Has(kFieldInstanceId)) cloud.instance_ids[i] = i * 7;
      if (cloud.Has(kFieldNormal)) cloud.normals[i] = Eigen::Vector3f(0, 0, -1);
    }
  }
  return cloud;
}

bool SameBits(const PointCloud& a, const PointCloud& b) {
  return a.size() == b.size() &&
         std::memcmp(a.positions.data(), b.positions.data(), a.size() * sizeof(Eigen::Vector3f)) == 0 &&
         a.ranges == b.ranges;
}

struct Moments {
  double mean = 0, sigma = 0;
};

Moments Measure(const std::vector<double>& v) {
  double sum = 0, sum2 = 0;
  for (double x : v) sum += x;
  const double mean = sum / v.size();
  for (double x : v) sum2 += (x - mean) * (x - mean);
  return {mean, std::sqrt(sum2 / (v.size() - 1))};
}

TEST(Distortion, MatchesBrownConrady) {
  const LensDistortion d{.k1 = -0.21, .k2 = 0.06, .k3 = -0.013, .p1 = 0.0012, .p2 = -0.0019};
  const PointCloud clean = PlaneCloud(2.0);
  PointCloud cloud = clean;
  ASSERT_TRUE(ApplyMeasurementModel(cloud, d, {}, 1).ok());
  ASSERT_EQ(cloud.size(), clean.size());
  double worst = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = clean.positions[i].cast<double>();
    const double x = p.x() / p.z(), y = p.y() / p.z();
    const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
    const double radial = 1 + d.k1 * r2 + d.k2 * r4 + d.k3 * r6;
    const double xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
    const double yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
    const Eigen::Vector3d expected(xd * p.z(), yd * p.z(), p.z());
    worst = std::max(worst, (cloud.positions[i].cast<double>() - expected).norm());
    EXPECT_EQ(cloud.positions[i].z(), clean.positions[i].z());
    EXPECT_NEAR(cloud.ranges[i], cloud.positions[i].norm(), 1e-6);
  }
  EXPECT_LT(worst, 1e-6);
  // The corner moves inwards under barrel distortion.
  EXPECT_LT(std::abs(cloud.positions[0].x()), std::abs(clean.positions[0].x()));
}

TEST(Distortion, ZeroCoefficientsAreIdentity) {
  const PointCloud clean = PlaneCloud(2.0, kFieldsAll);
  PointCloud cloud = clean;
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, {}, 9).ok());
  EXPECT_TRUE(SameBits(cloud, clean));
  EXPECT_EQ(cloud.pixels, clean.pixels);
  EXPECT_EQ(cloud.intensities, clean.intensities);
}

class IsotropicNoise : public ::testing::TestWithParam<double> {};

TEST_P(IsotropicNoise, PerAxisSigmaFollowsDepth) {
  const double z = GetParam();
  const DepthNoise noise{.sigma_a = 0.001, .sigma_b = 0.002, .sigma_c = 0.003};
  const double expected = noise.sigma_a + noise.sigma_b * z + noise.sigma_c * z * z;
  const PointCloud clean = PlaneCloud(z);
  PointCloud cloud = clean;
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, noise, 42).ok());
  ASSERT_EQ(cloud.size(), clean.size());
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> d(cloud.size());
    for (size_t i = 0; i < d.size(); ++i) d[i] = double{cloud.positions[i][axis]} - clean.positions[i][axis];
    const Moments m = Measure(d);
    std::printf("z=%.1f axis %d: sigma %.6f (expected %.6f), mean %.2e\n", z, axis, m.sigma, expected, m.mean);
    EXPECT_NEAR(m.sigma, expected, 0.03 * expected);
    EXPECT_LT(std::abs(m.mean), 0.02 * expected);
  }
  for (size_t i = 0; i < cloud.size(); ++i) ASSERT_NEAR(cloud.ranges[i], cloud.positions[i].norm(), 1e-5);
}

INSTANTIATE_TEST_SUITE_P(TwoDepths, IsotropicNoise, ::testing::Values(2.0, 5.0));

TEST(AlongRayNoise, DisplacementIsRadial) {
  const DepthNoise noise{.sigma_a = 0.002, .sigma_b = 0.001, .sigma_c = 0.004, .along_ray = true};
  const double expected = 0.002 + 0.001 * 2 + 0.004 * 4;
  const PointCloud clean = PlaneCloud(2.0);
  PointCloud cloud = clean;
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, noise, 7).ok());
  std::vector<double> along(cloud.size());
  double worst_perpendicular = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = clean.positions[i].cast<double>();
    const Eigen::Vector3d d = cloud.positions[i].cast<double>() - p;
    const Eigen::Vector3d dir = p.normalized();
    along[i] = d.dot(dir);
    worst_perpendicular = std::max(worst_perpendicular, (d - along[i] * dir).norm());
  }
  const Moments m = Measure(along);
  std::printf("along ray: sigma %.6f (expected %.6f), mean %.2e, max perpendicular %.2e\n", m.sigma, expected,
              m.mean, worst_perpendicular);
  EXPECT_NEAR(m.sigma, expected, 0.03 * expected);
  EXPECT_LT(std::abs(m.mean), 0.02 * expected);
  EXPECT_LT(worst_perpendicular, 1e-6);  // float storage only
}

TEST(Noise, SeedDeterminesBits) {
  const DepthNoise noise{.sigma_a = 0.01};
  PointCloud a = PlaneCloud(2.0), b = PlaneCloud(2.0), c = PlaneCloud(2.0);
  ASSERT_TRUE(ApplyMeasurementModel(a, {}, noise, 123).ok());
  ASSERT_TRUE(ApplyMeasurementModel(b, {}, noise, 123).ok());
  ASSERT_TRUE(ApplyMeasurementModel(c, {}, noise, 124).ok());
  EXPECT_TRUE(SameBits(a, b));
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += a.positions[i] != c.positions[i];
  EXPECT_GT(differ, a.size() * 99 / 100);
}

TEST(Noise, KeyedByPixelNotByOrder) {
  const DepthNoise noise{.sigma_a = 0.01};
  PointCloud forward = PlaneCloud(2.0);
  PointCloud reversed = forward;
  std::reverse(reversed.positions.begin(), reversed.positions.end());
  std::reverse(reversed.ranges.begin(), reversed.ranges.end());
  std::reverse(reversed.pixels.begin(), reversed.pixels.end());
  ASSERT_TRUE(ApplyMeasurementModel(forward, {}, noise, 5).ok());
  ASSERT_TRUE(ApplyMeasurementModel(reversed, {}, noise, 5).ok());
  const size_t n = forward.size();
  for (size_t i = 0; i < n; ++i) ASSERT_EQ(forward.positions[i], reversed.positions[n - 1 - i]);
}

TEST(Quantisation, DepthsAreMultiplesOfTheStep) {
  for (const double step : {1.0 / 1024, 0.001, 0.0037}) {
    PointCloud cloud = PlaneCloud(2.0);
    ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, {.sigma_a = 0.05, .depth_step = step}, 3).ok());
    ASSERT_EQ(cloud.size(), size_t{kWidth} * kHeight);
    // A dyadic step is exact in float; otherwise only float rounding of z remains.
    const double tolerance = step == 1.0 / 1024 ? 1e-9 : std::numeric_limits<float>::epsilon();
    for (const Eigen::Vector3f& p : cloud.positions) {
      const double z = p.z();
      ASSERT_LE(std::abs(z - std::round(z / step) * step), tolerance * z) << "step " << step << " z " << z;
    }
  }
}

TEST(Quantisation, ErrorIsUniformWithinHalfStepAndKeepsTheRay) {
  const double step = 0.001;
  const DepthNoise noisy{.sigma_a = 0.05};
  DepthNoise quantised = noisy;
  quantised.depth_step = step;
  PointCloud before = PlaneCloud(2.0), after = PlaneCloud(2.0);
  ASSERT_TRUE(ApplyMeasurementModel(before, {}, noisy, 11).ok());
  ASSERT_TRUE(ApplyMeasurementModel(after, {}, quantised, 11).ok());
  ASSERT_EQ(before.size(), after.size());
  constexpr int kBins = 10;
  std::vector<size_t> histogram(kBins, 0);
  std::vector<double> error(before.size());
  for (size_t i = 0; i < before.size(); ++i) {
    const Eigen::Vector3d b = before.positions[i].cast<double>(), a = after.positions[i].cast<double>();
    error[i] = a.z() - b.z();
    ASSERT_LE(std::abs(error[i]), step / 2 + 1e-6);
    ASSERT_LT((a.normalized() - b.normalized()).norm(), 1e-6);
    const int bin = std::clamp(static_cast<int>((error[i] / step + 0.5) * kBins), 0, kBins - 1);
    ++histogram[bin];
  }
  const Moments m = Measure(error);
  const double uniform_sigma = step / std::sqrt(12.0);
  std::printf("quantisation error: sigma %.3e (uniform %.3e), mean %.2e\n", m.sigma, uniform_sigma, m.mean);
  EXPECT_NEAR(m.sigma, uniform_sigma, 0.03 * uniform_sigma);
  EXPECT_LT(std::abs(m.mean), 0.02 * step);
  const double per_bin = error.size() / double{kBins};
  for (size_t count : histogram) EXPECT_NEAR(static_cast<double>(count), per_bin, 0.05 * per_bin);
}

TEST(Quantisation, DropsPointsQuantisedToZeroDepth) {
  PointCloud cloud = PlaneCloud(0.3);
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, {.depth_step = 1.0}, 0).ok());
  EXPECT_EQ(cloud.size(), 0u);
  EXPECT_TRUE(cloud.ranges.empty());
  EXPECT_TRUE(cloud.pixels.empty());
}

TEST(MinIntensity, DropsExactlyTheDimPoints) {
  const PointCloud clean = PlaneCloud(2.0, kFieldsAll);
  PointCloud cloud = clean;
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, {.min_intensity = 0.5}, 0).ok());
  std::vector<uint32_t> expected_pixels;
  for (size_t i = 0; i < clean.size(); ++i) {
    if (clean.intensities[i] >= 0.5f) expected_pixels.push_back(clean.pixels[i]);
  }
  ASSERT_EQ(expected_pixels.size(), clean.size() / 2);
  EXPECT_EQ(cloud.pixels, expected_pixels);
  for (size_t n : {cloud.normals.size(), cloud.ranges.size(), cloud.intensities.size(), cloud.instance_ids.size()}) {
    EXPECT_EQ(n, cloud.size());
  }
  for (size_t i = 0; i < cloud.size(); ++i) {
    const uint32_t source = cloud.pixels[i];
    EXPECT_GE(cloud.intensities[i], 0.5f);
    EXPECT_EQ(cloud.positions[i], clean.positions[source]);
    EXPECT_EQ(cloud.ranges[i], clean.ranges[source]);
    EXPECT_EQ(cloud.instance_ids[i], clean.instance_ids[source]);
    EXPECT_EQ(cloud.intensities[i], clean.intensities[source]);
  }
}

TEST(MinIntensity, IgnoredWithoutIntensities) {
  PointCloud cloud = PlaneCloud(2.0);
  ASSERT_TRUE(ApplyMeasurementModel(cloud, {}, {.min_intensity = 0.5}, 0).ok());
  EXPECT_EQ(cloud.size(), size_t{kWidth} * kHeight);
}

TEST(Validation, NamesTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto distortion_error = [](const LensDistortion& d) {
    return ValidateDistortion(d, "sensor.pinhole.distortion");
  };
  EXPECT_TRUE(distortion_error({.k1 = -0.3, .p2 = 0.01}).ok());
  Status s = distortion_error({.k1 = nan});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("sensor.pinhole.distortion.k1"), std::string::npos) << s.message();
  EXPECT_NE(distortion_error({.k3 = inf}).message().find("distortion.k3"), std::string::npos);
  EXPECT_NE(distortion_error({.p2 = -inf}).message().find("distortion.p2"), std::string::npos);

  const auto noise_error = [](const DepthNoise& n) { return ValidateNoise(n, "sensor.noise"); };
  EXPECT_TRUE(noise_error({.sigma_a = 0.001, .depth_step = 0.001, .min_intensity = 0.1}).ok());
  s = noise_error({.sigma_b = -0.1});
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("sensor.noise.sigma_b"), std::string::npos) << s.message();
  EXPECT_NE(noise_error({.sigma_a = nan}).message().find("sensor.noise.sigma_a"), std::string::npos);
  EXPECT_NE(noise_error({.sigma_c = inf}).message().find("sensor.noise.sigma_c"), std::string::npos);
  EXPECT_NE(noise_error({.depth_step = nan}).message().find("sensor.noise.depth_step_m"), std::string::npos);
  EXPECT_NE(noise_error({.min_intensity = -1}).message().find("sensor.noise.min_intensity"), std::string::npos);
}

TEST(Validation, ApplyRejectsBadInputWithoutTouchingTheCloud) {
  const PointCloud clean = PlaneCloud(2.0);
  PointCloud cloud = clean;
  Status s = ApplyMeasurementModel(cloud, {.k2 = std::numeric_limits<double>::quiet_NaN()}, {.sigma_a = 0.01}, 1);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("k2"), std::string::npos);
  EXPECT_TRUE(SameBits(cloud, clean));
  s = ApplyMeasurementModel(cloud, {}, {.depth_step = -1}, 1);
  EXPECT_NE(s.message().find("depth_step_m"), std::string::npos);
  cloud.ranges.pop_back();
  s = ApplyMeasurementModel(cloud, {}, {.sigma_a = 0.01}, 1);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("cloud.ranges"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace vscan::sensor
