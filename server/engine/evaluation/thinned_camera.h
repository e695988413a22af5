#pragma once
// A camera's image thinned to one pixel per stride x stride block: the same view through fewer,
// larger pixels, so that a virtual scan casts a bounded number of rays.

#include <cstdint>

#include "sensor/camera.h"

namespace vscan::evaluation {

// Pixels of the thinned image: whole blocks only (a partial block at the right or bottom edge is
// dropped), at least one in each direction.
uint64_t ThinnedPixelCount(const sensor::PinholeCamera& camera, uint32_t stride);

// The smallest stride whose thinned image has at most max_rays pixels (max_rays >= 1).
uint32_t BudgetStride(const sensor::PinholeCamera& camera, uint64_t max_rays);

// The largest stride (at least 1) whose neighbouring rays are at most spacing apart at distance
// from the sensor, measured across the rays.
uint32_t SpacingStride(const sensor::PinholeCamera& camera, double spacing, double distance);

// The thinned camera: each pixel's ray passes through the centre of its block of the original.
sensor::PinholeCamera ThinCamera(const sensor::PinholeCamera& camera, uint32_t stride);

}  // namespace vscan::evaluation
