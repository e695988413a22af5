#pragma once
// Planar structures larger than any part (a bin's floor, walls and rim, a table), found so that
// the search does not spend its votes on them.

#include <cstdint>
#include <vector>

#include "localization/oriented_points.h"

namespace vscan::localization {

struct LargePlaneSettings {
  double distance = 0.001;     // plane tolerance, metres
  double link = 0.004;         // points closer than this (about) are connected
  double min_extent = 0.1;     // a connected piece of a plane wider than this (bounding-box diagonal) is removed
  size_t min_points = 1000;    // planes with fewer inliers end the search
  size_t max_planes = 8;
  uint64_t seed = 1;
};

// Marks the points on connected pieces of planes (normals within 30 degrees of the plane's) whose
// extent exceeds min_extent; the planes are found one after another by RANSAC on the points not yet
// taken by a plane.
std::vector<bool> MarkLargePlanes(const OrientedPoints& cloud, const LargePlaneSettings& settings);

}  // namespace vscan::localization
