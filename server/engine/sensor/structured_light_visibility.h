#pragma once
// Which surface points a structured-light projector lights: the shadow test needs the scene, so it
// lives apart from the Embree-free sensor model (library vscan_structured_light).

#include <span>
#include <vector>

#include <Eigen/Core>

#include "raycast/raycast_scene.h"
#include "sensor/structured_light.h"
#include "vscan/common/pose.h"

namespace vscan::sensor {

// For each clean surface point (sensor frame; world_from_sensor places it in the scene):
// kUnlit when it lies outside the projector's field of view, else kShadowed when the segment from the
// projector to the point hits the scene before it, else kLit. The segment's last 1e-4 of its length
// (at least 10 um) is ignored so the surface does not shadow itself: points must be
// the clean hits, before noise. Non-finite points are kUnlit.
std::vector<ProjectorVisibility> ProjectorVisibilityOf(const raycast::RaycastScene& scene,
                                                       const Pose3& world_from_sensor, const StructuredLight& sl,
                                                       std::span<const Eigen::Vector3f> sensor_points);

}  // namespace vscan::sensor
