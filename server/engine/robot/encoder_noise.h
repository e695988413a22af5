#pragma once
// Joint-encoder noise: the configuration a robot actually reaches when commanded to q.

#include <cstdint>

#include <Eigen/Core>

#include "vscan/common/status.h"

namespace vscan::robot {

// q + N(0, sigma_i) per joint (radians for revolute, metres for prismatic joints). Reproducible:
// one std::mt19937_64 seeded with seed draws one standard normal per joint in order, scaled by
// sigma_i, so the same seed gives the same bits with the same standard library.
// InvalidArgument for mismatched sizes, a non-finite q or a negative or non-finite sigma.
// The result may leave the joint limits by a few sigma; ClampToLimits if that matters.
StatusOr<Eigen::VectorXd> AddEncoderNoise(const Eigen::VectorXd& q, const Eigen::VectorXd& sigma, uint64_t seed);

}  // namespace vscan::robot
