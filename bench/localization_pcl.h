#pragma once
// The benchmark peer of the baseline localizer: PCL's own pipeline, instance after instance.
// The plate is removed with SACSegmentation, both clouds are thinned with VoxelGrid, FPFH features
// (FPFHEstimationOMP) feed SampleConsensusPrerejective, pcl::IterativeClosestPoint refines, and
// the scan points the placed part covers are removed before the next instance.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::bench {

struct PclInstance {
  Pose3 world_from_part = Pose3::Identity();
  double score = 0;  // share of the thinned part's points with a scan point within the inlier distance
};

// model_points / model_normals: samples on the part's surface (outward normals), part frame.
// scan_points: world frame, without normals (estimated here, turned towards viewpoint).
// voxel: the fine length, as the baseline localizer's; features use 2.5 voxels.
std::vector<PclInstance> PclLocalize(std::span<const Eigen::Vector3f> model_points,
                                     std::span<const Eigen::Vector3f> model_normals,
                                     std::span<const Eigen::Vector3f> scan_points, const Eigen::Vector3f& viewpoint,
                                     double voxel, size_t max_instances);

}  // namespace vscan::bench
