#include "robot/encoder_noise.h"

#include <cmath>
#include <random>
#include <string>

namespace vscan::robot {

StatusOr<Eigen::VectorXd> AddEncoderNoise(const Eigen::VectorXd& q, const Eigen::VectorXd& sigma, uint64_t seed) {
  if (sigma.size() != q.size()) {
    return InvalidArgument("encoder_sigma", "expected " + std::to_string(q.size()) + " values (one per joint), got " +
                           std::to_string(sigma.size()));
  }
  if (!q.allFinite()) return InvalidArgument("joint_positions", "NaN or infinite value");
  for (int i = 0; i < sigma.size(); ++i) {
    if (!std::isfinite(sigma[i]) || sigma[i] < 0) {
      return InvalidArgument("encoder_sigma[" + std::to_string(i) + "]", "must be finite and >= 0");
    }
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> standard_normal(0.0, 1.0);
  Eigen::VectorXd noisy = q;
  // One draw per joint even when sigma is 0, so a joint's noise does not depend on its neighbours' sigmas.
  for (int i = 0; i < q.size(); ++i) noisy[i] += sigma[i] * standard_normal(rng);
  return noisy;
}

}  // namespace vscan::robot
