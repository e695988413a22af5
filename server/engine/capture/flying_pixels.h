#pragma once
// Flying pixels: at a depth edge the foreground pixel reports a depth mixed between the foreground
// and the background surface, as time-of-flight and stereo sensors do.

#include <cstdint>
#include <vector>

#include "capture/measurement_spec.h"
#include "sensor/camera.h"

namespace vscan::capture {

// A pixel with status MEASURED whose clean depth is more than e = spec.flying_pixels.edge_m in front
// of one of its 4-neighbours' (any clean hit not out of range) becomes FLYING_PIXEL when that
// neighbour's hit also lies more than e in depth off the pixel's tangent plane (so steep continuous
// surfaces have no edges): its depth moves along its ray to z + w (z_background - z), w uniform in
// [0, 1) seeded per pixel, z_background the farthest such neighbour. Returns how many pixels flew.
uint64_t MixDepthEdges(const PointCloud& clean, const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
                       std::vector<uint8_t>& status, std::vector<Eigen::Vector3f>& measured);

}  // namespace vscan::capture
