#pragma once
// What one candidate view sees: the hits of a virtual scan laid out on its image, and the samples
// that lie within tau of one of them.

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "evaluation/greedy_cover.h"
#include "raycast/raycast_scene.h"
#include "sensor/camera.h"
#include "sensor/material.h"
#include "sensor/pixel_radiometry.h"
#include "sensor/returned_signal.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::evaluation {

struct ViewHits {
  sensor::PinholeCamera camera;
  Pose3 frame_from_sensor = Pose3::Identity();
  // Hit positions in the frame; hit_of_pixel[v * width + u] indexes them, -1 where the pixel's ray
  // hit nothing usable.
  std::vector<Eigen::Vector3f> hits;
  std::vector<int32_t> hit_of_pixel;
};

// The sensor's own light on a surface of one material: a hit whose mean signal would be dark or
// saturated is not measurable there (docs/SENSORS.md, "The returned signal").
struct MeasurableLight {
  sensor::Emitter emitter;      // in the sensor frame
  sensor::PixelResponse pixel;  // gain_e of the sensor's own pixel (not a thinned image's)
  sensor::Material material;
  double ambient_irradiance_w_per_m2 = 0;  // fills the well and adds noise; does not decode
};

// Scans the scene through camera (depths within near..far) and keeps the hits whose surface meets
// the ray within max_incidence_deg of its normal and, with light, whose mean signal decodes.
// Cancelled when cancel turns true.
StatusOr<ViewHits> CastView(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                            const Pose3& frame_from_sensor, double max_incidence_deg,
                            const std::atomic<bool>* cancel, const MeasurableLight* light = nullptr);

// The samples within tau of a hit. Looks only at the hits whose pixels can hold one that near.
SampleBits SamplesNearHits(const ViewHits& view, std::span<const Eigen::Vector3f> samples, double tau);

}  // namespace vscan::evaluation
