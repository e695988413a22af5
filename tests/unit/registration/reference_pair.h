#pragma once
// The registration reference pair in data/registration: two noisy draws of one part, the source
// moved by a known transform.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"

namespace vscan::registration::testing {

struct Cloud {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> normals;
};

// Binary PCD with exactly the float fields x y z normal_x normal_y normal_z; fails the calling test
// (and returns an empty cloud) on anything else.
Cloud ReadPcdWithNormals(const std::string& path);

struct ReferencePair {
  Cloud source;
  Cloud target;
  // The transform that lays the source onto the target: the inverse of T_gt_src_from_tgt.txt.
  Pose3 target_from_source;
};

const ReferencePair& LoadReferencePair();

}  // namespace vscan::registration::testing
