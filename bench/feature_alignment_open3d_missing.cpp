#include "feature_alignment_open3d.h"

namespace vscan::bench {

bool Open3dAvailable() { return false; }

Open3dAlignment AlignWithOpen3d(const std::vector<Eigen::Vector3f>&, const std::vector<Eigen::Vector3f>&, double) {
  return {};
}

}  // namespace vscan::bench
