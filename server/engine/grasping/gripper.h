#pragma once
// The gripper a user describes: a suction cup or a pair of parallel jaws, in metres and degrees.

#include <variant>

#include "vscan/common/status.h"

namespace vscan::grasping {

struct SuctionCup {
  double diameter_m = 0.02;
  // How far the bellows compress; the column this high above the face must be free of the part.
  double stroke_m = 0.01;
  // How far off the cup's axis the surface normals under the cup may tilt and still seal.
  double max_tilt_deg = 10;
  // The share of the cup's disc the part must cover (not hanging over an edge or a hole), in (0, 1].
  double min_flat_fraction = 0.9;
};

struct ParallelJaws {
  double min_opening_m = 0.005;
  double max_opening_m = 0.05;
  // The finger pad: its width across the approach and its depth along the approach.
  double finger_width_m = 0.01;
  double finger_depth_m = 0.01;
  // Half-angle of the friction cone at each contact.
  double max_friction_angle_deg = 15;
  // The fingers' collision geometry: how far each reaches back from the pad's far edge to the
  // palm, and how thick it is across the closing axis.
  double finger_length_m = 0.04;
  double finger_thickness_m = 0.005;
};

using Gripper = std::variant<SuctionCup, ParallelJaws>;

// InvalidArgument naming the field ("gripper.suction.diameter_m", "gripper.jaws.max_opening_m", ...)
// for a non-finite, non-positive or out-of-range value. Lengths must lie in (0, 2] m.
Status ValidateGripper(const Gripper& gripper);

}  // namespace vscan::grasping
