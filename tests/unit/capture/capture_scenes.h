#pragma once
// Analytic scenes for the measurement-model tests: the sensor sits at the world origin looking
// along +z (world_from_sensor = identity), so sensor and world coordinates agree.

#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

#include "capture/measure_scan.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"

namespace vscan::capture::test {

constexpr uint32_t kPlaneId = 1, kSphereId = 2, kBoxId = 3;
inline constexpr double kDeg = std::numbers::pi / 180.0;

// A point's status as the cloud stores it.
constexpr uint8_t Code(PointStatus s) { return static_cast<uint8_t>(s); }

// Every field and the ground truth.
inline MeasurementSpec TruthSpec() {
  MeasurementSpec spec;
  spec.fields = kFieldsAll | kFieldsGroundTruth;
  return spec;
}

// A plane facing the sensor at depth z, half_size metres each side of the axis.
raycast::SceneInstance Plane(double z, double half_size);
// A sphere (icosphere, 6 subdivisions) of the given centre and radius.
raycast::SceneInstance Sphere(const Eigen::Vector3d& centre, double radius);
// An axis-aligned box.
raycast::SceneInstance Box(const Eigen::Vector3d& min, const Eigen::Vector3d& max);

std::shared_ptr<const raycast::RaycastScene> Build(std::vector<raycast::SceneInstance> instances);

sensor::PinholeCamera Camera(uint32_t width, uint32_t height, double hfov_deg, double far = 10.0);

// ScanMeasured in the sensor frame; fails the test on error.
PointCloud Measure(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                   const MeasurementSpec& spec, MeasureStats* stats = nullptr);

}  // namespace vscan::capture::test
