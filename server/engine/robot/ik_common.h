#pragma once
// Steps every IK solver shares: input checks, the reach gate, and packaging results.

#include <chrono>

#include <Eigen/Core>

#include "robot/chain.h"
#include "robot/ik_types.h"
#include "vscan/common/status.h"

namespace vscan::robot {

using IkClock = std::chrono::steady_clock;

// Validates goal and seed (InvalidArgument "seed: ..." for a wrong count or a non-finite value),
// then applies the reach gate when check_reach is set. Returns the seed clamped into the limits.
// On a reach failure *nearest (if given) describes the seed configuration.
StatusOr<Eigen::VectorXd> PrepareIkInputs(const KinematicChain& chain, const IkGoal& goal, const Eigen::VectorXd& seed,
                                          bool check_reach, IkClock::time_point start, IkResult* nearest);

// The result for configuration q: continuous joints wrapped into [-pi, pi], pose and errors measured.
IkResult MakeIkResult(const KinematicChain& chain, const IkGoal& goal, const double* q, int iterations, int restarts,
                      IkClock::time_point start);

bool WithinTolerance(const IkResult& result, double position_tolerance, double orientation_tolerance);

// OutOfRange naming how far the nearest configuration misses; fills *nearest when given.
Status NotReached(const IkResult& best, const char* solver, IkResult* nearest);

}  // namespace vscan::robot
