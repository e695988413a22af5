#pragma once
// A cloud made ready for feature matching: thinned to one point per voxel, with consistently
// oriented normals and evenly spread keypoints.

#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::registration {

struct FeatureCloud {
  std::vector<Eigen::Vector3f> points;
  // Unit length, one per point: towards the viewpoint when it is known, otherwise facing the same
  // side of the surface along each connected part (which side is the shape's call, see
  // OrientNormalsConsistently, and may differ between two views of one surface).
  std::vector<Eigen::Vector3f> normals;
  // Indices into points.
  std::vector<uint32_t> keypoints;
};

// The centroid of the finite points in each voxel of edge `voxel` (metres), in voxel order.
std::vector<Eigen::Vector3f> ThinToVoxels(std::span<const Eigen::Vector3f> points, double voxel);

// One point per cell of edge `spacing` (metres): the one nearest the cell's centre, in cell order.
std::vector<uint32_t> SpreadKeypoints(std::span<const Eigen::Vector3f> points, double spacing);

struct FeatureCloudOptions {
  double voxel = 0.003;
  double normal_radius = 0.009;
  double keypoint_spacing = 0.006;
  // Where the sensor stood, in the cloud's frame, when known: each normal is turned to face it.
  std::optional<Eigen::Vector3f> viewpoint;
  // Empty, or one per input point: a direction its surface faces (a mesh's face normal, or towards
  // the sensor that saw it). Each normal is turned to agree with its nearest input point's; this
  // orients the union of many views, or a sampled mesh, where no single viewpoint exists.
  std::span<const Eigen::Vector3f> facing;
  const std::atomic<bool>* cancel = nullptr;
};

// Thins, estimates normals from the neighbours within normal_radius (points with too few of them
// are dropped), orients them (towards the viewpoint, by facing, or consistently without either) and spreads the
// keypoints. Cancelled when cancel becomes true.
StatusOr<FeatureCloud> PrepareFeatureCloud(std::span<const Eigen::Vector3f> points, const FeatureCloudOptions& options);

}  // namespace vscan::registration
