#pragma once
// Thinning a cloud to one point per occupied voxel (the centroid of the points in it), and the
// voxel keys that thinning and the union of aligned scans share.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace vscan::registration {

// Voxels are cubes aligned on the origin; a key packs a voxel's integer coordinates in 21 bits
// each, so only voxels within 2^20 of the origin on every axis (2 km at 2 mm) have one.
std::optional<uint64_t> VoxelKey(const Eigen::Vector3f& point, double inverse_voxel_size);

// The centroid of each occupied voxel of edge voxel_size (> 0), in key order; non-finite points
// and points without a key are dropped. The same for any thread count.
std::vector<Eigen::Vector3f> ThinToVoxelCentroids(std::span<const Eigen::Vector3f> points, double voxel_size);

}  // namespace vscan::registration
