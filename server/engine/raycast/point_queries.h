#pragma once
// Closest-point queries against a RaycastScene's triangles (Embree's BVH), for distances from
// points to a surface. All coordinates are world coordinates.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "raycast/raycast_scene.h"

namespace vscan::raycast {

// Euclidean distance from each point to the nearest triangle of the scene, or +infinity when no
// triangle lies within max_distance (pass infinity for no limit); runs in parallel.
std::vector<float> DistancesToSurface(const RaycastScene& scene, std::span<const Eigen::Vector3f> points,
                                      float max_distance);

// The closest point of triangle (a, b, c) to p.
Eigen::Vector3f ClosestPointOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                       const Eigen::Vector3f& c);

}  // namespace vscan::raycast
