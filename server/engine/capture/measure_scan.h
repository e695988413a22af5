#pragma once
// Turns a clean sensor-frame scan into a measured one: rejection (out of range, grazing, dim, and
// with the returned light dark or saturated),
// outliers, flying pixels, distortion / noise / quantisation, ground truth and estimated normals.
// The order and the rules are documented in docs/SENSORS.md, "Measurement model".

#include <atomic>
#include <cstdint>
#include <span>

#include "capture/measurement_spec.h"
#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::capture {

struct MeasureStats {
  uint64_t hits = 0;    // clean hits looked at (depth range widened)
  uint64_t points = 0;  // returned measurements: measured + outliers + flying pixels
  uint64_t outliers = 0;
  uint64_t flying_pixels = 0;
  uint64_t rejected_out_of_range = 0;
  uint64_t rejected_shadowed = 0;
  uint64_t rejected_grazing = 0;
  uint64_t rejected_dim = 0;
  uint64_t rejected_unlit = 0;
  uint64_t rejected_dark = 0;
  uint64_t rejected_saturated = 0;
  uint64_t rejected_interreflection = 0;
  // Outlier rays that hit nothing and points quantised to a non-positive depth; never returned.
  uint64_t dropped = 0;
  double min_range = 0, max_range = 0;  // over the returned measurements
  double elapsed_ms = 0;

  uint64_t rejected() const {
    return rejected_out_of_range + rejected_shadowed + rejected_grazing + rejected_dim + rejected_unlit +
           rejected_dark + rejected_saturated + rejected_interreflection;
  }
};

// The camera with its depth range widened (near tiny, far x4), so that the clean scan also finds
// the surfaces that lie outside [near, far].
sensor::PinholeCamera ExtendedRangeCamera(const sensor::PinholeCamera& camera);

// The fields the clean scan under a measured one must have: position and pixel, and normal,
// intensity and instance id only where a verdict, an artefact or spec.fields reads them (ranges are
// recomputed from the positions).
uint32_t CleanFieldsFor(const MeasurementSpec& spec);

// clean: the clean scan in the sensor frame with (at least) CleanFieldsFor(spec), ideally taken with
// ExtendedRangeCamera(camera). Returns the measured cloud in the sensor frame with spec.fields;
// rejected rays only with spec.include_rejected, at their clean positions. scene is where outlier rays are re-cast (world_from_sensor places the sensor in it).
// cancel, when set, is polled by the long stages (normal estimation) and stops them with CANCELLED.
// direct_radiance, when given (one per clean point), is the returned light's direct term already
// evaluated per pixel (the raster shaders'); otherwise ReturnedSignals evaluates it per point.
StatusOr<PointCloud> MeasureScan(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                 const Pose3& world_from_sensor, PointCloud clean_sensor_cloud,
                                 const MeasurementSpec& spec, const std::atomic<bool>* cancel, MeasureStats* stats,
                                 std::span<const float> direct_radiance = {});

// The ray-cast scan with the measurement model: widened clean scan, MeasureScan, then the frame.
StatusOr<PointCloud> ScanMeasured(const raycast::RaycastScene& scene, const sensor::PinholeCamera& camera,
                                  const Pose3& world_from_sensor, const MeasurementSpec& spec,
                                  raycast::ScanFrame frame, const std::atomic<bool>* cancel,
                                  raycast::ScanStats* scan_stats, MeasureStats* stats);

// Moves a sensor-frame cloud into the world: positions, clean positions and every normal.
void SensorToWorld(const Pose3& world_from_sensor, PointCloud& cloud);

}  // namespace vscan::capture
