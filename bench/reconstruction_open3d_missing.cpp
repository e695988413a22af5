#include "reconstruction_open3d.h"

namespace vscan::bench {

bool Open3dAvailable() { return false; }

TriangleMesh Open3dPoisson(std::span<const Eigen::Vector3f>, std::span<const Eigen::Vector3f>, int) { return {}; }

}  // namespace vscan::bench
