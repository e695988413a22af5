#pragma once
// The production inverse-kinematics solver.

#include <Eigen/Core>

#include "robot/chain.h"
#include "robot/ik_types.h"
#include "vscan/common/status.h"

namespace vscan::robot {

// Levenberg-Marquardt on the 6-D twist error (position difference; rotation as the log map of
// R_goal R^T), with damping that shrinks as the error does (lambda = |e|^2 / 2 + 1e-7), joints
// resting on a limit locked for a step that would push them past it, limits enforced after every
// step (revolute joints spanning more than a turn wrap by 2 pi before clamping), and random
// restarts within the limits when an attempt stalls (< 1% progress in 5 iterations, or 100
// iterations in all). Look-at goals drop the rotation about tool z from the error and the
// Jacobian; position goals drop the rotation entirely.
//
// Success: position error <= position_tolerance and orientation error <= orientation_tolerance,
// as MeasureGoalErrors measures them. Otherwise OutOfRange with the distance and angle by which
// the best configuration misses, and *nearest (if given) describes it. Positions beyond
// ReachUpperBound fail immediately (OutOfRange) when options.check_reach is set.
StatusOr<IkResult> SolveIk(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                           const IkOptions& options = {}, IkResult* nearest = nullptr);

}  // namespace vscan::robot
