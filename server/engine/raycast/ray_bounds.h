#pragma once
// The rays Embree accepts. Its debug checks abort the process on a ray whose origin or direction
// has a component beyond about 1.8e18 or is NaN; vscan never hands it one.

#include <cmath>

#include <Eigen/Core>

namespace vscan::raycast {

// Far inside Embree's limit, and far beyond any position the physical bounds allow.
inline constexpr float kMaxRayComponent = 1e16f;

inline bool EmbreeAcceptsRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                             float t_far) {
  const auto bounded = [](const Eigen::Vector3f& v) {
    return v.allFinite() && v.cwiseAbs().maxCoeff() <= kMaxRayComponent;
  };
  return bounded(origin) && bounded(direction) && std::isfinite(t_near) && t_near >= 0 && !std::isnan(t_far);
}

}  // namespace vscan::raycast
