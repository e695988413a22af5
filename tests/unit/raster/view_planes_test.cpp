// Projection, depth mapping and scene-hugging planes, checked without a GL context.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "raster/view_planes.h"

namespace vscan::raster {
namespace {

sensor::PinholeCamera OffCentreCamera() {
  sensor::PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = 500;
  camera.fy = 520;
  camera.cx = 300.3;
  camera.cy = 250.7;
  camera.near = 0.5;
  camera.far = 20;
  return camera;
}

// Window coordinates (x, y, depth) of a sensor-frame point, as GL's viewport transform gives them.
Eigen::Vector3d Window(const Eigen::Matrix4d& clip_from_sensor, const Eigen::Vector3d& p, const sensor::PinholeCamera& c,
                       bool zero_to_one) {
  const Eigen::Vector4d clip = clip_from_sensor * p.homogeneous();
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  return {(ndc.x() + 1) / 2 * c.width, (ndc.y() + 1) / 2 * c.height, zero_to_one ? ndc.z() : (ndc.z() + 1) / 2};
}

TEST(ClipFromSensor, PixelCentresLandOnWindowPixelCentresAndDepthInverts) {
  const sensor::PinholeCamera camera = OffCentreCamera();
  for (bool reversed : {false, true}) {
    for (bool zero_to_one : {false, true}) {
      const Eigen::Matrix4d m = ClipFromSensor(camera, camera.near, camera.far, reversed, zero_to_one);
      for (const auto& [u, v] : {std::pair{0u, 0u}, std::pair{639u, 479u}, std::pair{100u, 200u}}) {
        for (double z : {0.5, 3.0, 20.0}) {
          const Eigen::Vector3d ray((u + 0.5 - camera.cx) / camera.fx, (v + 0.5 - camera.cy) / camera.fy, 1.0);
          const Eigen::Vector3d w = Window(m, z * ray, camera, zero_to_one);
          EXPECT_NEAR(w.x(), u + 0.5, 1e-9);
          EXPECT_NEAR(w.y(), v + 0.5, 1e-9) << "image row v must be GL window row v";
          EXPECT_NEAR(LinearDepth(w.z(), camera.near, camera.far, reversed), z, 1e-9 * z);
        }
      }
      const double at_near = Window(m, {0, 0, camera.near}, camera, zero_to_one).z();
      const double at_far = Window(m, {0, 0, camera.far}, camera, zero_to_one).z();
      EXPECT_NEAR(at_near, reversed ? 1.0 : 0.0, 1e-12);
      EXPECT_NEAR(at_far, reversed ? 0.0 : 1.0, 1e-12);
    }
  }
}

TEST(LinearDepth, MatchesThePapersFormulaOnNdcDepth) {
  const double n = 0.1, f = 50;
  for (double d : {0.0, 0.3, 0.9, 0.999, 1.0}) {
    const double ndc = 2 * d - 1;
    EXPECT_NEAR(LinearDepth(d, n, f, false), 2 * n * f / (f + n - ndc * (f - n)), 1e-12);
  }
}

TEST(PlanesForScene, HugTheBoxAlongTheView) {
  sensor::PinholeCamera camera = OffCentreCamera();
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, -1, 4), Eigen::Vector3d(1, 1, 6));
  const ViewPlanes p = PlanesForScene(camera, Pose3::Identity(), box, true);
  ASSERT_FALSE(p.empty);
  EXPECT_LE(p.near, 4.0);
  EXPECT_GT(p.near, 3.99);
  EXPECT_GE(p.far, 6.0);
  EXPECT_LT(p.far, 6.01);
  EXPECT_DOUBLE_EQ(p.near_range, 4.0);
  EXPECT_DOUBLE_EQ(p.far_range, std::sqrt(38.0));

  const ViewPlanes own = PlanesForScene(camera, Pose3::Identity(), box, false);
  EXPECT_EQ(own.near, camera.near);
  EXPECT_EQ(own.far, camera.far);
  EXPECT_EQ(own.near_range, camera.near);
  EXPECT_DOUBLE_EQ(own.far_range, camera.far * MaxRayLength(camera));
}

TEST(PlanesForScene, StayInsideTheCamerasPlanes) {
  const sensor::PinholeCamera camera = OffCentreCamera();
  const Eigen::AlignedBox3d around(Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 30));
  const ViewPlanes p = PlanesForScene(camera, Pose3::Identity(), around, true);
  EXPECT_EQ(p.near, camera.near);
  EXPECT_EQ(p.far, camera.far);
  EXPECT_FALSE(p.empty);
}

TEST(PlanesForScene, EmptyWhenTheSceneIsOutOfRange) {
  const sensor::PinholeCamera camera = OffCentreCamera();
  const Eigen::AlignedBox3d behind(Eigen::Vector3d(-1, -1, -6), Eigen::Vector3d(1, 1, -4));
  const Eigen::AlignedBox3d beyond(Eigen::Vector3d(-1, -1, 25), Eigen::Vector3d(1, 1, 26));
  EXPECT_TRUE(PlanesForScene(camera, Pose3::Identity(), behind, true).empty);
  EXPECT_TRUE(PlanesForScene(camera, Pose3::Identity(), beyond, true).empty);
  EXPECT_TRUE(PlanesForScene(camera, Pose3::Identity(), Eigen::AlignedBox3d(), true).empty);
}

TEST(PlanesForScene, FollowTheSensorPose) {
  const sensor::PinholeCamera camera = OffCentreCamera();
  const Eigen::AlignedBox3d box(Eigen::Vector3d(9, -1, -1), Eigen::Vector3d(11, 1, 1));
  // Sensor at the origin looking along world +x.
  Pose3 world_from_sensor = Pose3::Identity();
  world_from_sensor.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const ViewPlanes p = PlanesForScene(camera, world_from_sensor, box, true);
  ASSERT_FALSE(p.empty);
  EXPECT_NEAR(p.near, 9.0, 0.01);
  EXPECT_NEAR(p.far, 11.0, 0.01);
}

}  // namespace
}  // namespace vscan::raster
