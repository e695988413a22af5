#include "localization/support_plane.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "random/seeded_draws.h"

namespace vscan::localization {
namespace {

constexpr int kHypotheses = 300;
// Hypotheses are counted on an evenly strided subset of at most this many points.
constexpr size_t kCountedPoints = 4000;

size_t CountInliers(std::span<const Eigen::Vector3f> points, size_t stride, const Plane& plane, double distance) {
  size_t n = 0;
  for (size_t i = 0; i < points.size(); i += stride) n += plane.Distance(points[i]) <= distance ? 1 : 0;
  return n;
}

// Least-squares plane through the points within distance of `plane`.
Plane Refit(std::span<const Eigen::Vector3f> points, const Plane& plane, double distance) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> inliers;
  for (const auto& p : points) {
    if (plane.Distance(p) <= distance) inliers.push_back(p.cast<double>());
  }
  for (const auto& p : inliers) sum += p;
  const Eigen::Vector3d centre = sum / static_cast<double>(inliers.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : inliers) scatter += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  Plane refit;
  refit.normal = solver.eigenvectors().col(0);
  refit.offset = -refit.normal.dot(centre);
  return refit;
}

}  // namespace

std::optional<Plane> FindDominantPlane(std::span<const Eigen::Vector3f> points, double distance, double min_share,
                                       uint64_t seed) {
  if (points.size() < 3) return std::nullopt;
  const size_t stride = std::max<size_t>(1, points.size() / kCountedPoints);
  random::SplitMix64Stream draws(seed);
  const auto pick = [&] {
    return points[std::min(points.size() - 1, static_cast<size_t>(draws.Uniform() * points.size()))].cast<double>();
  };
  Plane best;
  size_t best_count = 0;
  for (int h = 0; h < kHypotheses; ++h) {
    const Eigen::Vector3d a = pick(), b = pick(), c = pick();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    Plane plane;
    plane.normal = n.normalized();
    plane.offset = -plane.normal.dot(a);
    const size_t count = CountInliers(points, stride, plane, distance);
    if (count > best_count) {
      best = plane;
      best_count = count;
    }
  }
  if (best_count < 3) return std::nullopt;
  Plane plane = Refit(points, best, distance);
  plane.inliers = 0;
  for (const auto& p : points) plane.inliers += plane.Distance(p) <= distance ? 1 : 0;
  if (static_cast<double>(plane.inliers) < min_share * static_cast<double>(points.size())) return std::nullopt;
  return plane;
}

}  // namespace vscan::localization
