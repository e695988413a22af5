#pragma once
// The triangle mesh of an open bin: a floor and four walls as boxes, laid out as the bin fill's
// physics lays them out, so that scans see the walls the parts rested against.

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::geometry {

// Bin frame: the floor's inner surface at z = 0, centred in x and y, the rim at z = inner_size.z();
// the floor is wall_thickness thick below z = 0 and the walls stand around the inner box.
TriangleMesh OpenBinMesh(const Eigen::Vector3d& inner_size, double wall_thickness);

}  // namespace vscan::geometry
