#pragma once
// Planar structures larger than any part (a bin's floor, walls and rim, a table), found so that
// the search does not spend its votes on them.

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "localization/oriented_points.h"

namespace vscan::localization {

struct LargePlaneSettings {
  double distance = 0.001;     // plane tolerance, metres
  double link = 0.004;         // points closer than this (about) are connected
  double min_extent = 0.1;     // a connected piece of a plane wider than this (bounding-box diagonal) is removed
  size_t min_points = 1000;    // planes with fewer inliers end the search
  size_t max_planes = 8;
  uint64_t seed = 1;
  // The normal of the plane the parts stand on, when known: a wide piece parallel to it is taken
  // for a structure only when it fills less than max_parallel_fill of its bounding rectangle (a
  // bin's rim is a thin ring; flat parts lying side by side fill theirs).
  std::optional<Eigen::Vector3d> support_normal;
  double max_parallel_fill = 0.5;
};

// Marks the points on connected pieces of planes (normals within 30 degrees of the plane's) whose
// extent exceeds min_extent (and, parallel to the support, that fill little of their rectangle);
// the planes are found one after another by RANSAC on the points not yet taken by a plane.
std::vector<bool> MarkLargePlanes(const OrientedPoints& cloud, const LargePlaneSettings& settings);

}  // namespace vscan::localization
