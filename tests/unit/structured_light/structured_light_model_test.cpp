// Validation and projector pose of the structured-light model.

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "sensor/structured_light.h"

namespace vscan::sensor {
namespace {

StructuredLight ValidScanner() {
  StructuredLight sl;
  sl.camera = CameraFromFov(320, 240, 60.0, 0.1, 5.0);
  sl.projector_offset = {0.1, 0, 0};
  return sl;
}

void ExpectModelRejected(const StructuredLight& sl, const std::string& field_prefix) {
  const Status status = ValidateStructuredLight(sl, "sensor.structured_light");
  EXPECT_FALSE(status.ok()) << field_prefix;
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument) << status.ToString();
  EXPECT_TRUE(status.message().starts_with(field_prefix)) << status.message();
}

TEST(StructuredLightValidation, AcceptsParallelAndConvergedScanners) {
  StructuredLight sl = ValidScanner();
  EXPECT_TRUE(ValidateStructuredLight(sl, "sl").ok());
  sl.convergence_distance = 0.8;
  sl.disparity_step_px = 0.25;
  sl.projector_hfov_deg = 50;
  sl.projector_vfov_deg = 40;
  EXPECT_TRUE(ValidateStructuredLight(sl, "sl").ok());
}

TEST(StructuredLightValidation, NamesTheOffendingField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  StructuredLight sl = ValidScanner();
  sl.camera.fx = 0;
  ExpectModelRejected(sl, "sensor.structured_light.camera.fx");

  sl = ValidScanner();
  sl.projector_offset = {0, 0, 0.1};
  ExpectModelRejected(sl, "sensor.structured_light.projector_offset:");
  sl.projector_offset = {nan, 0, 0};
  ExpectModelRejected(sl, "sensor.structured_light.projector_offset:");
  sl.projector_offset = {20, 0, 0};
  ExpectModelRejected(sl, "sensor.structured_light.projector_offset:");

  sl = ValidScanner();
  sl.projector_hfov_deg = 180;
  ExpectModelRejected(sl, "sensor.structured_light.projector_horizontal_fov_deg:");
  sl = ValidScanner();
  sl.projector_vfov_deg = -1;
  ExpectModelRejected(sl, "sensor.structured_light.projector_vertical_fov_deg:");

  sl = ValidScanner();
  sl.disparity_step_px = -0.5;
  ExpectModelRejected(sl, "sensor.structured_light.disparity_step_px:");
  sl.disparity_step_px = std::numeric_limits<double>::infinity();
  ExpectModelRejected(sl, "sensor.structured_light.disparity_step_px:");

  sl = ValidScanner();
  sl.convergence_distance = -1;
  ExpectModelRejected(sl, "sensor.structured_light.convergence_distance:");
  sl.projector_offset = {0.1, 0, 0.5};
  sl.convergence_distance = 0.4;  // behind the projector
  ExpectModelRejected(sl, "sensor.structured_light.convergence_distance:");
}

TEST(SensorFromProjector, ParallelAxesKeepTheCameraOrientation) {
  StructuredLight sl = ValidScanner();
  sl.projector_offset = {0.2, -0.05, 0.01};
  const Pose3 pose = SensorFromProjector(sl);
  EXPECT_TRUE(pose.translation().isApprox(sl.projector_offset));
  EXPECT_TRUE(pose.linear().isApprox(Eigen::Matrix3d::Identity()));
}

TEST(SensorFromProjector, ConvergedAxisPassesThroughTheConvergencePoint) {
  StructuredLight sl = ValidScanner();
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0.15, 0, 0), Eigen::Vector3d(-0.3, 0, 0),
                                        Eigen::Vector3d(0.2, 0.05, 0.03), Eigen::Vector3d(0, -0.1, 0)}) {
    sl.projector_offset = offset;
    sl.convergence_distance = 0.9;
    const Pose3 pose = SensorFromProjector(sl);
    const Eigen::Vector3d origin = pose.translation();
    const Eigen::Vector3d axis = pose.linear().col(2);
    const Eigen::Vector3d target(0, 0, 0.9);
    EXPECT_TRUE(origin.isApprox(offset));
    // The projector looks at the convergence point: the axis points to it, not away from it.
    EXPECT_NEAR(axis.dot((target - origin).normalized()), 1.0, 1e-12);
    EXPECT_NEAR((target - origin).cross(axis).norm(), 0.0, 1e-12);
    // The turn is about an axis perpendicular to the baseline and to the camera axis.
    const Eigen::AngleAxisd turn(pose.linear());
    EXPECT_NEAR(turn.axis().dot(offset.normalized()), 0.0, 1e-12);
    EXPECT_NEAR(turn.axis().z(), 0.0, 1e-12);
    EXPECT_TRUE(pose.linear().isUnitary(1e-12));
    EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  }
}

TEST(ProjectorField, UsesTheCamerasFieldWhenUnset) {
  StructuredLight sl = ValidScanner();
  EXPECT_NEAR(ProjectorHorizontalFovDeg(sl), 60.0, 1e-9);
  const double vfov = 2 * std::atan(120.0 / sl.camera.fy) * 180 / std::numbers::pi;
  EXPECT_NEAR(ProjectorVerticalFovDeg(sl), vfov, 1e-9);
  sl.projector_hfov_deg = 30;
  EXPECT_DOUBLE_EQ(ProjectorHorizontalFovDeg(sl), 30);
  // Edge of a 30 degree field seen from the projector at x = 0.1: tan(15 deg) at depth 1.
  const ProjectorField field(sl);
  const double edge = 0.1 + std::tan(15.0 * std::numbers::pi / 180.0);
  EXPECT_TRUE(field.Contains({edge - 1e-6, 0, 1}));
  EXPECT_FALSE(field.Contains({edge + 1e-6, 0, 1}));
  EXPECT_FALSE(field.Contains({0.1, 0, -1}));
}

}  // namespace
}  // namespace vscan::sensor
