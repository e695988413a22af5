#pragma once
// Arbitrary rays against a RaycastScene, for what the pixel grid scanner does not cover:
// projector shadow tests and perturbed (outlier) rays. All coordinates are world coordinates.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "raycast/raycast_scene.h"

namespace vscan::raycast {

struct RayHit {
  bool hit = false;
  float distance = 0;              // along the unit direction
  Eigen::Vector3f normal{0, 0, 0};  // unit geometric normal, facing the ray's origin
  uint32_t instance_id = 0;
};

// Nearest hit of each ray (origins[i], directions[i] unit) within [t_near, t_far]; runs in parallel.
std::vector<RayHit> IntersectRays(const RaycastScene& scene, std::span<const Eigen::Vector3f> origins,
                                  std::span<const Eigen::Vector3f> directions, float t_near, float t_far);

// 1 where something lies on the segment from[i] -> to[i], excluding a margin at each end of
// max(min_margin, relative_margin * the segment's length) metres (so the surface a segment ends on
// does not shadow itself); 0 where the segment is free.
std::vector<uint8_t> OccludedSegments(const RaycastScene& scene, std::span<const Eigen::Vector3f> from,
                                      std::span<const Eigen::Vector3f> to, float relative_margin,
                                      float min_margin);

// One ray's nearest hit, for loops that already run in parallel (the indirect light's bounces).
RayHit IntersectRay(const RaycastScene& scene, const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                    float t_near, float t_far);
// Whether something lies on the segment from -> to, `margin` metres excluded at each end.
bool SegmentOccluded(const RaycastScene& scene, const Eigen::Vector3f& from, const Eigen::Vector3f& to, float margin);

}  // namespace vscan::raycast
