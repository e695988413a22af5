#pragma once
// A measured ray-cast scan as a benchmark case: a call that scans and returns the point count, and
// stops the benchmark with the error when the scan fails.

#include <cstddef>
#include <functional>

#include "capture/measure_scan.h"

namespace vscan::bench {

// scene and camera must outlive the returned call.
std::function<size_t()> MeasuredScan(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                     const Pose3& world_from_sensor, capture::MeasurementSpec spec);

}  // namespace vscan::bench
