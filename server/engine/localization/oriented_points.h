#pragma once
// Points with unit normals, and thinning them to one point per voxel and normal direction (the
// normal-aware subsampling of Vidal et al. 2018: a voxel on an edge keeps a point per face).

#include <numbers>
#include <vector>

#include <Eigen/Core>

namespace vscan::localization {

// Points of one voxel whose normals differ by more than this are kept apart (an edge's two faces).
inline constexpr double kFaceSplitAngleRad = 30 * std::numbers::pi / 180;

struct OrientedPoints {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;  // unit, one per point
};

// Per voxel of edge voxel (> 0), the points are grouped by normal: a point joins the first group
// whose mean normal is within max_normal_angle_rad of its own, else starts one. Each group gives
// its centroid and its mean normal. The same input gives the same output, in voxel-key order.
// Non-finite points and points outside the voxel keys' range are dropped.
OrientedPoints ThinOriented(const OrientedPoints& cloud, double voxel, double max_normal_angle_rad);

}  // namespace vscan::localization
