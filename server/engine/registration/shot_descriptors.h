#pragma once
// SHOT descriptors (Tombari, Salti, Di Stefano 2010) of chosen points of a cloud, computed by PCL.

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::registration {

struct ShotDescriptors {
  static constexpr int kLength = 352;
  // The keypoints whose descriptor could be computed (a local frame needs a few neighbours), as
  // indices into the cloud, in the order they were given.
  std::vector<uint32_t> points;
  // One column of kLength values per entry of points.
  Eigen::MatrixXf values;
};

// Describes the keypoints (indices into points) by the points and normals within `radius`
// (metres). Same inputs, same descriptors, whatever the thread count. Cancelled when cancel becomes
// true (polled between batches of keypoints).
StatusOr<ShotDescriptors> DescribeWithShot(std::span<const Eigen::Vector3f> points,
                                           std::span<const Eigen::Vector3f> normals,
                                           std::span<const uint32_t> keypoints, double radius,
                                           const std::atomic<bool>* cancel);

}  // namespace vscan::registration
