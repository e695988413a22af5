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

// A PCD file with positions and normals (vscan's reader); fails the calling test (and returns an
// empty cloud) when it cannot be read or has no normals.
Cloud ReadPcdWithNormals(const std::string& path);

struct ReferencePair {
  Cloud source;
  Cloud target;
  // The transform that lays the source onto the target: the inverse of T_gt_src_from_tgt.txt.
  Pose3 target_from_source;
};

const ReferencePair& LoadReferencePair();

}  // namespace vscan::registration::testing
