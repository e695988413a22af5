#pragma once
// Open3D 0.16 (Debian libopen3d-dev) as a benchmark peer for alignment without a pose: voxel
// thinning, FPFH, RANSAC over feature matches with edge-length and distance checkers, then
// point-to-plane ICP. Open3D stays in the .cpp.

#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::bench {

struct Open3dAlignment {
  Pose3 target_from_source = Pose3::Identity();
  double fitness = 0;  // Open3D's, after ICP
};

// True when the peer is compiled in.
bool Open3dAvailable();

// Open3D's documented global registration recipe at this voxel edge (metres).
Open3dAlignment AlignWithOpen3d(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                                double voxel);

}  // namespace vscan::bench
