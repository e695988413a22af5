#pragma once
// Colour maps for points: Turbo for scalars, distinct hues for instance ids.

#include <cstdint>

#include <Eigen/Core>

namespace vscan::render {

// Google's Turbo map (Mikhailov, 2019) from its published polynomial fit; t is clamped to [0, 1],
// 0 dark blue through green to 1 dark red. RGB in [0, 1].
Eigen::Vector3f Turbo(float t);

// Instance 0 (background, no object) is mid grey; every other id gets a saturated hue stepped by
// the golden ratio, so consecutive ids are far apart on the colour wheel.
Eigen::Vector3f InstanceColour(uint32_t id);

inline constexpr float kInstanceZeroGrey = 0.5f;

}  // namespace vscan::render
