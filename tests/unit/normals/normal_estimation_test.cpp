#include "normals/normal_estimation.h"

#include <algorithm>
#include <limits>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "spatial/kd_tree.h"

namespace vscan::normals {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// In double and via atan2: acos of a float dot product cannot resolve angles below ~0.03 deg.
double AngleDeg(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const Eigen::Vector3d x = a.cast<double>(), y = b.cast<double>();
  return std::atan2(x.cross(y).norm(), x.dot(y)) * kRadToDeg;
}

// Angle between lines: the sign of a normal is not what these tests measure.
double UnsignedAngleDeg(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const double angle = AngleDeg(a, b);
  return std::min(angle, 180.0 - angle);
}

struct Plane {
  Eigen::Vector3d origin{1.0, -2.0, 3.0};
  Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  Eigen::Vector3d u = normal.unitOrthogonal();
  Eigen::Vector3d v = normal.cross(u);
};

// n points uniform on a side x side square of the plane, with isotropic Gaussian noise sigma.
std::vector<Eigen::Vector3f> SamplePlane(const Plane& plane, size_t n, double side, double sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-side / 2, side / 2);
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  std::vector<Eigen::Vector3f> points(n);
  for (auto& p : points) {
    Eigen::Vector3d x = plane.origin + u(rng) * plane.u + u(rng) * plane.v;
    if (sigma > 0) x += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    p = x.cast<float>();
  }
  return points;
}

std::vector<Eigen::Vector3f> Estimate(const std::vector<Eigen::Vector3f>& points, const NormalOptions& options) {
  auto normals = EstimateNormals(points, options);
  EXPECT_TRUE(normals.ok()) << normals.status().ToString();
  return normals.ok() ? *normals : std::vector<Eigen::Vector3f>{};
}

TEST(NormalEstimationTest, ExactPlane) {
  const Plane plane;
  const auto points = SamplePlane(plane, 20000, 1.0, 0.0, 1);
  const auto normals = Estimate(points, {.orient_towards_viewpoint = false});
  ASSERT_EQ(normals.size(), points.size());
  double worst = 0.0;
  for (const auto& n : normals) {
    EXPECT_NEAR(n.norm(), 1.0f, 1e-5f);
    worst = std::max(worst, UnsignedAngleDeg(n, plane.normal.cast<float>()));
  }
  EXPECT_LT(worst, 0.01);
}

// With k points spread uniformly over a disc of radius r and noise sigma across the plane, the
// least-squares slope along each in-plane axis has standard deviation sigma / sqrt(k r^2 / 4), so
// the tilt is Rayleigh-distributed with mean sqrt(pi/2) * 2 sigma / (r sqrt(k)); r follows from the
// density, pi r^2 rho = k.
TEST(NormalEstimationTest, NoisyPlaneWithinTheoreticalTilt) {
  const Plane plane;
  const size_t n = 40000;
  const double side = 1.0, sigma = 0.001;
  const int k = 16;
  const auto points = SamplePlane(plane, n, side, sigma, 2);
  const auto normals = Estimate(points, {.k = k, .orient_towards_viewpoint = false});
  const double r = std::sqrt(k / (std::numbers::pi * (n / (side * side))));
  const double expected_mean_deg = std::sqrt(std::numbers::pi / 2) * 2 * sigma / (r * std::sqrt(k)) * kRadToDeg;
  double sum = 0.0;
  for (const auto& nrm : normals) sum += UnsignedAngleDeg(nrm, plane.normal.cast<float>());
  const double mean = sum / static_cast<double>(n);
  EXPECT_LT(mean, 1.3 * expected_mean_deg);
  EXPECT_GT(mean, 0.5 * expected_mean_deg);  // the noise is really there: the model, not luck
}

// Points uniform on a sphere of radius R. The plane fitted to a neighbourhood on a sphere is
// perpendicular to the radius through the neighbourhood's middle, which lies within the
// neighbourhood, so a point's error is at most the angle its farthest neighbour subtends at the
// centre. The middle is the mean of k scattered points around the query, about 1/sqrt(k) of that
// angle away on average, so the mean error is bounded by a fraction of the typical angle.
TEST(NormalEstimationTest, SphereNormalsAreRadial) {
  const size_t n = 20000;
  const float radius = 0.5f;
  const int k = 16;
  const Eigen::Vector3f centre(0.2f, 0.1f, -0.3f);
  std::mt19937 rng(3);
  std::normal_distribution<float> g(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> points(n);
  for (auto& p : points) p = centre + radius * Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized();

  const auto normals = Estimate(points, {.k = k, .viewpoint = centre});
  const spatial::KdTree tree(points);
  std::vector<spatial::Neighbor> nb(k);
  double sum_error = 0.0, sum_subtended = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const size_t found = tree.Knn(points[i], std::numeric_limits<float>::infinity(), nb);
    const double farthest = std::sqrt(nb[found - 1].dist_sq);
    const double subtended_deg = 2.0 * std::asin(farthest / (2.0 * radius)) * kRadToDeg;
    // Oriented towards the centre, so against the outward radius.
    const double error = AngleDeg(normals[i], centre - points[i]);
    EXPECT_LE(error, subtended_deg) << "point " << i;
    sum_error += error;
    sum_subtended += subtended_deg;
  }
  const double mean_error = sum_error / n, mean_subtended = sum_subtended / n;
  EXPECT_LT(mean_error, 2.0 * mean_subtended / std::sqrt(k));
}

TEST(NormalEstimationTest, OrientsTowardsViewpoint) {
  const Plane plane;
  const auto points = SamplePlane(plane, 5000, 1.0, 0.0005, 4);
  const Eigen::Vector3f front = (plane.origin + 2.0 * plane.normal).cast<float>();
  const Eigen::Vector3f back = (plane.origin - 2.0 * plane.normal).cast<float>();
  const auto towards_front = Estimate(points, {.viewpoint = front});
  const auto towards_back = Estimate(points, {.viewpoint = back});
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_GT(towards_front[i].dot(front - points[i]), 0.0f);
    EXPECT_GT(towards_back[i].dot(back - points[i]), 0.0f);
  }
}

TEST(NormalEstimationTest, MaxDistanceCutLeavesIsolatedPointWithoutNormal) {
  const Plane plane;
  auto points = SamplePlane(plane, 2000, 0.2, 0.0, 5);
  points.push_back((plane.origin + 5.0 * plane.normal).cast<float>());
  points.push_back(points.back() + Eigen::Vector3f(0.01f, 0.0f, 0.0f));

  const auto cut = Estimate(points, {.max_distance = 0.05f});
  EXPECT_TRUE(cut[points.size() - 1].array().isNaN().all());
  EXPECT_TRUE(cut[points.size() - 2].array().isNaN().all());
  for (size_t i = 0; i + 2 < points.size(); ++i) EXPECT_TRUE(cut[i].allFinite()) << i;

  // Without the cut the far pair borrows neighbours from the plane and gets some normal.
  const auto uncut = Estimate(points, {.max_distance = 0.0f});
  EXPECT_TRUE(uncut.back().allFinite());
}

TEST(NormalEstimationTest, DegenerateInputs) {
  EXPECT_TRUE(Estimate({}, {}).empty());
  const std::vector<Eigen::Vector3f> two{{0, 0, 0}, {1, 0, 0}};
  for (const auto& n : Estimate(two, {})) EXPECT_TRUE(n.array().isNaN().all());

  const Plane plane;
  auto points = SamplePlane(plane, 1000, 0.2, 0.0, 6);
  points[3].y() = std::numeric_limits<float>::quiet_NaN();
  const auto normals = Estimate(points, {});
  EXPECT_TRUE(normals[3].array().isNaN().all());
  EXPECT_TRUE(normals[4].allFinite());
}

TEST(NormalEstimationTest, RejectsBadOptions) {
  const std::vector<Eigen::Vector3f> points(10, Eigen::Vector3f::Zero());
  auto expect_invalid = [&](const NormalOptions& options, const char* field) {
    const auto result = EstimateNormals(points, options);
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
    EXPECT_NE(result.status().message().find(field), std::string::npos) << result.status().message();
  };
  expect_invalid({.k = 2}, "normals.k");
  expect_invalid({.k = 257}, "normals.k");
  expect_invalid({.max_distance = -0.1f}, "normals.max_distance");
  expect_invalid({.max_distance = std::numeric_limits<float>::quiet_NaN()}, "normals.max_distance");
  expect_invalid({.max_distance = std::numeric_limits<float>::infinity()}, "normals.max_distance");
  EXPECT_TRUE(EstimateNormals(points, {.k = 3}).ok());
  EXPECT_TRUE(EstimateNormals(points, {.k = 256}).ok());
}

TEST(NormalEstimationTest, HonoursCancellation) {
  const Plane plane;
  const auto points = SamplePlane(plane, 1000, 0.2, 0.0, 7);
  const std::atomic<bool> cancel{true};
  const auto result = EstimateNormals(points, {.cancel = &cancel});
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::normals
