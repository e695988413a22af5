#pragma once
// A noise-free ray-cast scan of copies of a fixture part (data/parts/angle_block.STL) standing on a
// square plate at known poses, for the localizer tests.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/point_cloud.h"
#include "vscan/common/pose.h"

namespace vscan::localization::testing {

// The angle block in metres (its file is in inches), in its own frame.
std::shared_ptr<const TriangleMesh> AngleBlock();

// Poses of `count` (1 to 4) copies standing on the plane z = 0, turned about z, 9 cm or more apart.
std::vector<Pose3> StandingPoses(size_t count);

// A 640 x 480 depth scan (world frame, positions and normals) of the copies at the given poses on
// a plate of side plate_side centred on the origin, seen from above at an angle.
PointCloud ScanParts(const std::vector<Pose3>& world_from_part, double plate_side);

}  // namespace vscan::localization::testing
