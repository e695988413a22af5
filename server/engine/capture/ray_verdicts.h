#pragma once
// First verdict on every clean hit: incidence angle, then out of range, grazing or dim.

#include <cstdint>
#include <vector>

#include "capture/measurement_spec.h"
#include "sensor/camera.h"

namespace vscan::capture {

// clean: sensor frame, with normals and intensities. Fills status (MEASURED or the rejection
// reason, checked in the order out of range, grazing, dim) and incidence (radians, between the ray
// and the true normal) for every point.
void JudgeRays(const PointCloud& clean, const sensor::PinholeCamera& camera, const MeasurementSpec& spec,
               std::vector<uint8_t>& status, std::vector<float>& incidence);

}  // namespace vscan::capture
