#pragma once
// How far the tool can get from the robot: a guaranteed bound and a sampled estimate.

#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "robot/chain.h"
#include "vscan/common/status.h"

namespace vscan::robot {

// Origin of the first moving joint in the base frame; no joint position moves it.
Eigen::Vector3d FirstJointOrigin(const KinematicChain& chain);

// Upper bound on |tool origin - first joint origin| over all joint positions: the sum of the
// lengths of the fixed offsets after the first joint (tool offset included) plus each prismatic
// joint's largest travel. Rotations preserve lengths, so no configuration can exceed it.
double ReachUpperBound(const KinematicChain& chain);

// The same distance maximised over `samples` configurations drawn uniformly in the sampling
// ranges: a lower bound on the true reach, usually a tighter figure than ReachUpperBound.
double SampledReach(const KinematicChain& chain, int samples, uint64_t seed);

// OutOfRange "<field>: ... misses by d m" when base_position lies farther than ReachUpperBound
// from the first joint origin; d is that excess distance. *miss_distance gets d (0 when within).
Status CheckWithinReach(const KinematicChain& chain, const Eigen::Vector3d& base_position, std::string_view field,
                        double* miss_distance = nullptr);

}  // namespace vscan::robot
