#pragma once
// The plane the parts stand on, found by RANSAC, so that the scan of each part becomes a surface of
// its own: feature alignment orients normals per connected surface, and a part joined to a large
// plate would take its orientation from the plate.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include <Eigen/Core>

namespace vscan::localization {

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  double offset = 0;                                    // normal . x + offset = 0 on the plane
  size_t inliers = 0;

  double Distance(const Eigen::Vector3f& p) const { return std::abs(normal.dot(p.cast<double>()) + offset); }
};

// The plane with the most points within `distance` (seeded RANSAC over three-point samples, then a
// least-squares refit to its inliers), if it holds at least min_share of the points.
std::optional<Plane> FindDominantPlane(std::span<const Eigen::Vector3f> points, double distance, double min_share,
                                       uint64_t seed);

}  // namespace vscan::localization
