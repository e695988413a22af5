#pragma once
// Parts made for the localizer tests, not taken from the fixtures: a many-sided prism (a nut's
// hull), an L-shaped bracket with flat machined faces, and a thin square pin; each with the
// symmetries BOP would declare for it.

#include <memory>

#include "localization/part_symmetries.h"
#include "vscan/common/mesh.h"

namespace vscan::localization::testing {

struct MadePart {
  std::shared_ptr<const TriangleMesh> mesh;  // metres, resting on z = 0 in its own frame
  PartSymmetries symmetries;
};

// A right prism over a regular polygon of `sides` corners at `radius` about the z axis, z in [0, height].
MadePart Prism(int sides, double radius, double height);

// An L-shaped plate (arms of length long_arm along x and short_arm along y, width `arm_width`),
// z in [0, thickness]; no symmetry.
MadePart Bracket(double long_arm, double short_arm, double arm_width, double thickness);

// A square rod of side `side` along x from 0 to length, z in [0, side].
MadePart SquarePin(double length, double side);

}  // namespace vscan::localization::testing
