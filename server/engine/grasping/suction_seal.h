#pragma once
// Whether a suction cup seals on a surface at a point: the flatness, tilt and coverage test behind
// the suction grasps, shared by grasp generation and the check of a grasp on a part's true pose.

#include <vector>

#include <Eigen/Core>

#include "grasping/gripper.h"
#include "grasping/surface_samples.h"

namespace vscan::grasping {

struct SealCheck {
  bool sealed = false;
  double quality = 0;
};

// The cup's disc as a k x k grid of cells whose centres lie inside it; coverage is the share of
// those cells holding at least one in-plane sample.
struct DiscCells {
  int k = 4;
  std::vector<char> inside;
  int count = 0;
  explicit DiscCells(int cells);
};

// Cells about two sample spacings wide, so that a covered cell almost surely holds a sample.
DiscCells DiscCellsFor(const SurfaceSamples& dense, const SuctionCup& cup);

// The cup centred on p with its face in the plane of the unit normal n: sealed when every dense
// sample under the disc (and in the cup's column up to its stroke) lies within tolerance of the
// plane with a normal within max_tilt_deg of n, and the in-plane samples cover min_flat_fraction.
SealCheck CheckSeal(const SurfaceSamples& dense, const SampleGrid& grid, const DiscCells& disc,
                    const Eigen::Vector3d& p, const Eigen::Vector3d& n, const SuctionCup& cup, double tolerance);

}  // namespace vscan::grasping
