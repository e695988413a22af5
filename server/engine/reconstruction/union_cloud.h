#pragma once
// The union of several scans with duplicate density evened out: one point per occupied voxel
// (the centroid of the points in it), with the mean direction towards the sensors that saw it.

#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::reconstruction {

// One scan's points (world frame) and the sensor position they were seen from.
struct ScanPoints {
  std::span<const Eigen::Vector3f> points;
  Eigen::Vector3f sensor_origin = Eigen::Vector3f::Zero();
};

struct UnionCloud {
  std::vector<Eigen::Vector3f> positions;
  // Unit vector from each point towards the sensors that saw it (the mean of the unit directions).
  std::vector<Eigen::Vector3f> view_directions;
};

// Voxels are cubes of edge voxel_size aligned on the origin; the output is in voxel-key order,
// the same for any thread count. Non-finite points are dropped. voxel_size must be positive.
UnionCloud VoxelDownsample(std::span<const ScanPoints> scans, float voxel_size);

}  // namespace vscan::reconstruction
