#pragma once
// An exact test of whether a triangle meets an axis-aligned box (the separating-axis theorem over
// the box's 3 axes, the triangle's normal and the 9 edge cross products), written apart from the
// collision engine so that its verdicts can be checked.

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::grasping::testing {

bool TriangleMeetsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

// Whether any triangle of mesh, placed in the box's frame by box_from_mesh, meets the box.
bool MeshMeetsBox(const TriangleMesh& mesh, const Pose3& box_from_mesh, const Eigen::Vector3d& lo,
                  const Eigen::Vector3d& hi);

}  // namespace vscan::grasping::testing
