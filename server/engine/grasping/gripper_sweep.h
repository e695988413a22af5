#pragma once
// The space a gripper occupies on its way in: its collision geometry in the tool frame (z along
// the approach, origin at the tool centre point), swept back along -z from the pre-grasp pose.

#include <vector>

#include "grasping/gripper.h"
#include "vscan/common/mesh.h"

namespace vscan::grasping {

struct ToolSweep {
  // From the tool centre point back to the flange along -z: the cup's stem or the jaws' palm.
  double body_length_m = 0.1;
  // The straight approach: the pre-grasp pose stands this far back along -z.
  double approach_m = 0.05;
};

// Convex pieces (closed meshes, metres): a suction cup is one cylinder of its diameter from the
// face (z = 0) back over the body and the approach; jaws are two open fingers (at max_opening,
// the pads reaching finger_depth / 2 past z = 0) and a palm behind them, each swept the same way.
// Cylinders are circumscribed prisms, so the pieces never fall inside the true shape.
std::vector<TriangleMesh> GripperSweep(const Gripper& gripper, const ToolSweep& sweep);

// An axis-aligned box and a circumscribed z-prism, as closed triangle meshes wound outwards.
TriangleMesh BoxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
TriangleMesh CylinderMesh(double radius, double z_lo, double z_hi, int sides = 24);

}  // namespace vscan::grasping
