#pragma once
// Normals of a union cloud, each turned to face the sensors that saw its point (outward for a
// closed object scanned from outside).

#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::reconstruction {

struct OrientedCloud {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;
};

// k-nearest-neighbour plane fits (vscan_normals); points whose normal cannot be estimated are
// dropped. view_directions[i] points from positions[i] towards its sensors.
StatusOr<OrientedCloud> OrientNormals(std::span<const Eigen::Vector3f> positions,
                                      std::span<const Eigen::Vector3f> view_directions, int k);

}  // namespace vscan::reconstruction
