#include "sensor/structured_light.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <Eigen/Geometry>

#include "vscan/common/physical_limits.h"

namespace vscan::sensor {
namespace {

constexpr double kMaxOffset = 10.0;        // metres
constexpr double kMaxDisparityStep = 1e3;  // pixels

Status ValidateFov(double fov, std::string_view field, std::string_view member) {
  if (!std::isfinite(fov) || fov < 0 || fov >= 180) {
    return InvalidArgument(FieldPath(field, member), "must be 0 (the camera's) or in (0, 180) degrees");
  }
  return Status::Ok();
}

double CameraFovDeg(double size_px, double focal_px) {
  return 2.0 * std::atan(size_px / (2.0 * focal_px)) * 180.0 / std::numbers::pi;
}

double HalfTan(double fov_deg) { return std::tan(fov_deg * std::numbers::pi / 360.0); }

double InverseConvergence(const StructuredLight& sl) {
  return sl.convergence_distance > 0 ? 1.0 / sl.convergence_distance : 0.0;
}

}  // namespace

Status ValidateStructuredLight(const StructuredLight& sl, std::string_view field) {
  RETURN_IF_ERROR(ValidateCamera(sl.camera, FieldPath(field, "camera"), std::numeric_limits<uint64_t>::max()));
  const Eigen::Vector3d& o = sl.projector_offset;
  const std::string offset = FieldPath(field, "projector_offset");
  if (!AllFinite(o)) return InvalidArgument(offset, "NaN or infinite value");
  if (o.norm() > kMaxOffset) return InvalidArgument(offset, "at most 10 m from the camera");
  if (!(o.head<2>().norm() > 0)) {
    return InvalidArgument(offset, "must have a component across the camera axis (x or y); the baseline is zero");
  }
  RETURN_IF_ERROR(ValidateFov(sl.projector_hfov_deg, field, "projector_horizontal_fov_deg"));
  RETURN_IF_ERROR(ValidateFov(sl.projector_vfov_deg, field, "projector_vertical_fov_deg"));
  if (!std::isfinite(sl.disparity_step_px) || sl.disparity_step_px < 0 || sl.disparity_step_px > kMaxDisparityStep) {
    return InvalidArgument(FieldPath(field, "disparity_step_px"), "must be in [0, 1000] pixels");
  }
  const double zc = sl.convergence_distance;
  if (!std::isfinite(zc) || zc < 0 || zc > kMaxFarM) {
    return InvalidArgument(FieldPath(field, "convergence_distance") +
                           ": must be in [0, 1e5] metres (0: parallel axes)");
  }
  if (zc > 0 && zc <= o.z()) {
    return InvalidArgument(FieldPath(field, "convergence_distance") +
                           ": must lie in front of the projector (greater than projector_offset.z)");
  }
  return Status::Ok();
}

Pose3 SensorFromProjector(const StructuredLight& sl) {
  Pose3 pose = Pose3::Identity();
  pose.translation() = sl.projector_offset;
  if (sl.convergence_distance > 0) {
    const Eigen::Vector3d axis = Eigen::Vector3d(0, 0, sl.convergence_distance) - sl.projector_offset;
    pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
  }
  return pose;
}

double ProjectorHorizontalFovDeg(const StructuredLight& sl) {
  return sl.projector_hfov_deg > 0 ? sl.projector_hfov_deg : CameraFovDeg(sl.camera.width, sl.camera.fx);
}

double ProjectorVerticalFovDeg(const StructuredLight& sl) {
  return sl.projector_vfov_deg > 0 ? sl.projector_vfov_deg : CameraFovDeg(sl.camera.height, sl.camera.fy);
}

ProjectorField::ProjectorField(const StructuredLight& sl)
    : projector_from_sensor_(SensorFromProjector(sl).inverse()),
      tan_half_h_(HalfTan(ProjectorHorizontalFovDeg(sl))),
      tan_half_v_(HalfTan(ProjectorVerticalFovDeg(sl))) {}

bool ProjectorField::Contains(const Eigen::Vector3d& sensor_point) const {
  const Eigen::Vector3d p = projector_from_sensor_ * sensor_point;
  if (!(p.z() > 0)) return false;
  return std::abs(p.x()) <= p.z() * tan_half_h_ && std::abs(p.y()) <= p.z() * tan_half_v_;
}

double DisparityBaseline(const StructuredLight& sl) { return sl.projector_offset.head<2>().norm(); }

double DisparityFocalPx(const StructuredLight& sl) {
  const Eigen::Vector2d u = sl.projector_offset.head<2>().normalized();
  return std::hypot(sl.camera.fx * u.x(), sl.camera.fy * u.y());
}

double DisparityAtDepth(const StructuredLight& sl, double depth) {
  return DisparityFocalPx(sl) * DisparityBaseline(sl) * (1.0 / depth - InverseConvergence(sl));
}

double DepthAtDisparity(const StructuredLight& sl, double disparity_px) {
  const double inverse_depth = disparity_px / (DisparityFocalPx(sl) * DisparityBaseline(sl)) + InverseConvergence(sl);
  return inverse_depth > 0 ? 1.0 / inverse_depth : 0.0;
}

void QuantiseDisparity(const StructuredLight& sl, std::span<Eigen::Vector3f> sensor_points) {
  const double step = sl.disparity_step_px;
  if (step <= 0) return;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Eigen::Vector3f& p : sensor_points) {
    const double z = p.z();
    if (!(z > 0) || !std::isfinite(z)) continue;
    const double quantised = step * std::round(DisparityAtDepth(sl, z) / step);
    const double z_q = DepthAtDisparity(sl, quantised);
    if (!(z_q > 0) || !std::isfinite(z_q)) {
      p.setConstant(nan);
      continue;
    }
    p = (p.cast<double>() * (z_q / z)).cast<float>();
  }
}

}  // namespace vscan::sensor
