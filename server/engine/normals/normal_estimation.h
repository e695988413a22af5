#pragma once
// Per-point surface normals from k nearest neighbours (the paper's method), parallel over points.

#include <atomic>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::normals {

struct NormalOptions {
  // Neighbours per point, the point itself included; in [3, 256].
  int k = 16;
  // Neighbours farther than this from the point are dropped; 0 keeps all k.
  float max_distance = 0.0f;
  Eigen::Vector3f viewpoint = Eigen::Vector3f::Zero();
  // Flip each normal so that it faces the viewpoint; otherwise the sign is arbitrary.
  bool orient_towards_viewpoint = true;
  // Polled while working; when it becomes true the call returns Cancelled.
  const std::atomic<bool>* cancel = nullptr;
};

// One unit normal per input point, in input order. A point with fewer than 3 neighbours left
// after the distance cut, or with a non-finite coordinate, gets a NaN normal.
// InvalidArgument names "normals.k" or "normals.max_distance" when an option is out of range.
StatusOr<std::vector<Eigen::Vector3f>> EstimateNormals(std::span<const Eigen::Vector3f> points,
                                                        const NormalOptions& options);

}  // namespace vscan::normals
