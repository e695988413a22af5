#pragma once
// A structured-light triangulation scanner: a pinhole camera and a projector a baseline apart.
// A surface point is measured only where the projector lights it; its depth comes from the
// disparity between the camera and the projector, quantised to the decoder's step.

#include <cstdint>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "sensor/camera.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::sensor {

struct StructuredLight {
  PinholeCamera camera;
  // Projector position in the camera (sensor) frame, metres: x right, y down, z forward.
  Eigen::Vector3d projector_offset{0.1, 0, 0};
  // Full projector field of view in degrees; 0 means the same as the camera's.
  double projector_hfov_deg = 0, projector_vfov_deg = 0;
  // Disparity quantisation step in pixels; 0 means no quantisation.
  double disparity_step_px = 0;
  // The projector's optical axis meets the camera's z axis at this depth, metres; 0 means parallel axes.
  double convergence_distance = 0;
};

// Checks the camera (without a ray limit), the offset, the fields of view, the step and the
// convergence; messages start with field, e.g. "sensor.structured_light.projector_offset: ...".
Status ValidateStructuredLight(const StructuredLight& sl, std::string_view field);

// The projector's pose in the camera frame: its position is the offset; its axis is parallel to the
// camera's, or turned about the axis perpendicular to both the baseline and the camera axis so that it
// meets the camera axis at (0, 0, convergence_distance).
Pose3 SensorFromProjector(const StructuredLight& sl);

// Full projector field of view actually used (the camera's when the setting is 0), degrees.
double ProjectorHorizontalFovDeg(const StructuredLight& sl);
double ProjectorVerticalFovDeg(const StructuredLight& sl);

// The projector's field of view as a test on sensor-frame points.
class ProjectorField {
 public:
  explicit ProjectorField(const StructuredLight& sl);
  // True when the point lies in front of the projector and inside its field of view.
  bool Contains(const Eigen::Vector3d& sensor_point) const;

 private:
  Pose3 projector_from_sensor_;
  double tan_half_h_, tan_half_v_;
};

// Triangulation baseline: the length of the offset's component across the camera axis (x, y), metres.
double DisparityBaseline(const StructuredLight& sl);
// Focal length in pixels along the baseline direction: fx for an x offset, fy for a y offset.
double DisparityFocalPx(const StructuredLight& sl);
// d = f * b * (1/z - 1/z_c), with 1/z_c = 0 for parallel axes.
double DisparityAtDepth(const StructuredLight& sl, double depth);
// Inverse of DisparityAtDepth; 0 or negative when the disparity belongs to no depth in front of the camera.
double DepthAtDisparity(const StructuredLight& sl, double disparity_px);

enum class ProjectorVisibility : uint8_t { kLit, kUnlit, kShadowed };

// Moves each sensor-frame point along its camera ray to the depth of its quantised disparity
// d_q = step * round(d / step). No-op when disparity_step_px is 0. A point whose quantised disparity
// maps to no positive finite depth (parallel axes: d_q = 0, i.e. infinitely far) becomes NaN.
void QuantiseDisparity(const StructuredLight& sl, std::span<Eigen::Vector3f> sensor_points);

}  // namespace vscan::sensor
