#include "raycast/scanner.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "vscan_test/ascii_ply.h"
#include "vscan_test/mesh_distance.h"
#include "vscan_test/meshes.h"

namespace vscan::raycast {
namespace {

// A sensor at eye looking at target, with z up in the world: a pose that is not axis-aligned.
Pose3 LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  auto pose = PoseFromLookAt(eye, target, Eigen::Vector3d::UnitZ(), "test");
  EXPECT_TRUE(pose.ok());
  return *pose;
}

const Eigen::Vector3d kEye(1.0, -2.0, 0.5);
const Eigen::Vector3d kTarget(0.2, 0.3, 0.1);

std::shared_ptr<const RaycastScene> BuildScene(std::vector<SceneInstance> instances) {
  auto scene = RaycastScene::Build(instances);
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  return scene.ok() ? *scene : nullptr;
}

SceneInstance Instance(TriangleMesh mesh, uint32_t id, const Pose3& world_from_object = Pose3::Identity()) {
  SceneInstance instance;
  instance.mesh = test::Share(std::move(mesh));
  instance.world_from_object = world_from_object;
  instance.instance_id = id;
  return instance;
}

PointCloud ScanOk(const RaycastScene& scene, const sensor::PinholeCamera& camera, const Pose3& pose,
                  ScanFrame frame, uint32_t fields = kFieldsAll, ScanStats* stats = nullptr) {
  ScanOptions options;
  options.fields = fields;
  options.frame = frame;
  auto cloud = Scan(scene, camera, pose, options, stats);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  return cloud.ok() ? std::move(cloud).value() : PointCloud{};
}

Eigen::Vector3d D(const Eigen::Vector3f& v) { return v.cast<double>(); }

// A plane perpendicular to the view at depth d: every pixel sees it at depth exactly d.
class PlaneTest : public ::testing::Test {
 protected:
  static constexpr double kDepth = 2.5;
  Pose3 pose_ = LookAt(kEye, kTarget);
  Eigen::Vector3d forward_ = pose_.linear().col(2);
  std::shared_ptr<const RaycastScene> scene_ =
      BuildScene({Instance(test::MakeSquare(kEye + kDepth * forward_, forward_, 20.0), 5)});
};

TEST_F(PlaneTest, SensorFrameDepthRangeAndNormal) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(64, 48, 60.0, 0.1, 10.0);
  ScanStats stats;
  const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kSensor, kFieldsAll, &stats);
  ASSERT_EQ(cloud.size(), camera.pixel_count());
  ASSERT_EQ(cloud.fields, static_cast<uint32_t>(kFieldsAll));
  double min_range = std::numeric_limits<double>::infinity(), max_range = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(cloud.pixels[i], i);
    const Eigen::Vector3d dir = D(camera.RayThroughPixel(i % camera.width, i / camera.width));
    EXPECT_NEAR(cloud.positions[i].z(), kDepth, 1e-5 * kDepth);
    EXPECT_LT((D(cloud.positions[i]) - kDepth * dir).norm(), 1e-5 * kDepth);
    EXPECT_NEAR(cloud.ranges[i], kDepth * dir.norm(), 1e-5 * kDepth);
    EXPECT_LT((D(cloud.normals[i]) - Eigen::Vector3d(0, 0, -1)).norm(), 1e-5);
    EXPECT_EQ(cloud.instance_ids[i], 5u);
    min_range = std::min<double>(min_range, cloud.ranges[i]);
    max_range = std::max<double>(max_range, cloud.ranges[i]);
  }
  EXPECT_EQ(stats.rays, camera.pixel_count());
  EXPECT_EQ(stats.points, cloud.size());
  EXPECT_DOUBLE_EQ(stats.min_range, min_range);
  EXPECT_DOUBLE_EQ(stats.max_range, max_range);
  // A steady clock in nanoseconds sees a scan of thousands of rays take time, and not minutes.
  EXPECT_GT(stats.elapsed_ms, 0.0);
  EXPECT_LT(stats.elapsed_ms, 60e3);
}

TEST_F(PlaneTest, WorldFramePointsFollowThePose) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(64, 48, 60.0, 0.1, 10.0);
  const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kWorld);
  ASSERT_EQ(cloud.size(), camera.pixel_count());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d dir = D(camera.RayThroughPixel(i % camera.width, i / camera.width));
    EXPECT_LT((D(cloud.positions[i]) - pose_ * (kDepth * dir)).norm(), 1e-5 * kDepth);
    EXPECT_LT((D(cloud.normals[i]) + forward_).norm(), 1e-5);
  }
}

TEST_F(PlaneTest, ImageSizesThatAreNotWholePackets) {
  for (const auto& [width, height] : {std::pair{1u, 1u}, std::pair{3u, 5u}, std::pair{37u, 23u}}) {
    const sensor::PinholeCamera camera = sensor::CameraFromFov(width, height, 50.0, 0.1, 10.0);
    const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kSensor);
    ASSERT_EQ(cloud.size(), camera.pixel_count()) << width << "x" << height;
    for (size_t i = 0; i < cloud.size(); ++i) {
      ASSERT_EQ(cloud.pixels[i], i);
      EXPECT_NEAR(cloud.positions[i].z(), kDepth, 1e-5 * kDepth);
    }
  }
}

TEST_F(PlaneTest, NearAndFarClip) {
  sensor::PinholeCamera camera = sensor::CameraFromFov(32, 24, 60.0, 0.1, kDepth - 0.5);
  EXPECT_EQ(ScanOk(*scene_, camera, pose_, ScanFrame::kSensor).size(), 0u);  // beyond far
  camera.far = kDepth + 0.5;
  EXPECT_EQ(ScanOk(*scene_, camera, pose_, ScanFrame::kSensor).size(), camera.pixel_count());
  camera.near = kDepth + 0.1;
  camera.far = 10.0;
  EXPECT_EQ(ScanOk(*scene_, camera, pose_, ScanFrame::kSensor).size(), 0u);  // nearer than near
}

TEST_F(PlaneTest, OnlyTheRequestedFields) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(32, 24, 60.0, 0.1, 10.0);
  const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kSensor, kFieldPosition | kFieldPixel);
  EXPECT_EQ(cloud.fields, static_cast<uint32_t>(kFieldPosition | kFieldPixel));
  EXPECT_EQ(cloud.size(), camera.pixel_count());
  EXPECT_EQ(cloud.pixels.size(), cloud.size());
  EXPECT_TRUE(cloud.normals.empty());
  EXPECT_TRUE(cloud.ranges.empty());
  EXPECT_TRUE(cloud.intensities.empty());
  EXPECT_TRUE(cloud.instance_ids.empty());
}

TEST(ScannerTest, IntensityFollowsTheAttenuationFormula) {
  const Pose3 pose = LookAt(kEye, kTarget);
  // A plane 2 m ahead, tilted 35 degrees about the sensor's x axis.
  const double tilt = 35.0 * std::numbers::pi / 180.0;
  const Eigen::Vector3d normal_sensor(0.0, std::sin(tilt), -std::cos(tilt));
  const Eigen::Vector3d centre = pose * Eigen::Vector3d(0, 0, 2.0);
  auto scene = BuildScene({Instance(test::MakeSquare(centre, pose.linear() * normal_sensor, 20.0), 1)});
  sensor::PinholeCamera camera = sensor::CameraFromFov(48, 40, 70.0, 0.1, 20.0);
  camera.lighting = {3.0, 0.5, 0.4, 0.3};

  const PointCloud cloud = ScanOk(*scene, camera, pose, ScanFrame::kSensor);
  ASSERT_EQ(cloud.size(), camera.pixel_count());
  double lowest = std::numeric_limits<double>::infinity(), highest = 0;
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d p = D(cloud.positions[i]);
    const double r = p.norm();
    const double cos_incidence = std::abs(normal_sensor.dot(p / r));
    const double expected = 3.0 * cos_incidence / (0.5 + 0.4 * r + 0.3 * r * r);
    EXPECT_NEAR(cloud.ranges[i], r, 1e-5 * r);
    EXPECT_NEAR(cloud.intensities[i], expected, 1e-4 * expected);
    EXPECT_NEAR(cloud.intensities[i], sensor::Intensity(camera.lighting, r, cos_incidence), 1e-4 * expected);
    lowest = std::min<double>(lowest, cloud.intensities[i]);
    highest = std::max<double>(highest, cloud.intensities[i]);
  }
  EXPECT_GT(highest, 1.5 * lowest);  // the tilt makes intensity vary across the image
}

class SphereTest : public ::testing::Test {
 protected:
  static constexpr double kRadius = 0.5;
  static constexpr double kDistance = 3.0;
  Pose3 pose_ = LookAt(kEye, kTarget);
  Eigen::Vector3d centre_ = pose_ * Eigen::Vector3d(0, 0, kDistance);
  TriangleMesh mesh_ = test::MakeIcosphere(centre_, kRadius, 4);
  std::shared_ptr<const RaycastScene> scene_ = BuildScene({Instance(mesh_, 3)});
};

TEST_F(SphereTest, PointsLieOnTheSphereWithRadialNormals) {
  // Tessellation bounds: how far inside the sphere a face gets, and how far a face normal turns
  // from the radius over the face.
  double inner = kRadius, turn = 0;
  for (const auto& t : mesh_.triangles) {
    const Eigen::Vector3d a = D(mesh_.vertices[t[0]]) - centre_, b = D(mesh_.vertices[t[1]]) - centre_,
                          c = D(mesh_.vertices[t[2]]) - centre_;
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    inner = std::min(inner, std::abs(n.dot(a)));
    for (const Eigen::Vector3d& v : {a, b, c}) turn = std::max(turn, std::acos(std::min(1.0, std::abs(n.dot(v.normalized())))));
  }
  ASSERT_LT(kRadius - inner, 0.01 * kRadius);

  const sensor::PinholeCamera camera = sensor::CameraFromFov(320, 240, 60.0, 0.1, 10.0);
  const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kWorld);
  ASSERT_GT(cloud.size(), 1000u);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d radial = D(cloud.positions[i]) - centre_;
    EXPECT_GE(radial.norm(), inner - 1e-5);
    EXPECT_LE(radial.norm(), kRadius + 1e-5);
    const double angle = std::acos(std::clamp(D(cloud.normals[i]).dot(radial.normalized()), -1.0, 1.0));
    EXPECT_LE(angle, turn + 1e-3);
    EXPECT_NEAR(D(cloud.normals[i]).norm(), 1.0, 1e-5);
    EXPECT_EQ(cloud.instance_ids[i], 3u);
  }

  // The silhouette of a sphere on the optical axis is a disc of radius f R / sqrt(D^2 - R^2).
  const double disc = camera.fx * kRadius / std::sqrt(kDistance * kDistance - kRadius * kRadius);
  const double expected = std::numbers::pi * disc * disc;
  EXPECT_NEAR(static_cast<double>(cloud.size()), expected, 0.02 * expected);
}

TEST_F(SphereTest, RowMajorPixelOrderAndVisibleSide) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(96, 72, 60.0, 0.1, 10.0);
  const PointCloud cloud = ScanOk(*scene_, camera, pose_, ScanFrame::kSensor);
  ASSERT_GT(cloud.size(), 100u);
  for (size_t i = 1; i < cloud.size(); ++i) EXPECT_LT(cloud.pixels[i - 1], cloud.pixels[i]);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_LE(cloud.positions[i].z(), kDistance + 1e-5);  // only the near half is seen
    EXPECT_LT(cloud.normals[i].dot(cloud.positions[i]), 0.0f);  // normals face the sensor
  }
}

TEST_F(SphereTest, WorldAndSensorFramesDifferByThePose) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(80, 60, 60.0, 0.1, 10.0);
  const PointCloud world = ScanOk(*scene_, camera, pose_, ScanFrame::kWorld);
  const PointCloud sensor = ScanOk(*scene_, camera, pose_, ScanFrame::kSensor);
  ASSERT_EQ(world.size(), sensor.size());
  ASSERT_GT(world.size(), 100u);
  for (size_t i = 0; i < world.size(); ++i) {
    ASSERT_EQ(world.pixels[i], sensor.pixels[i]);
    EXPECT_LT((D(world.positions[i]) - pose_ * D(sensor.positions[i])).norm(), 1e-5);
    EXPECT_LT((D(world.normals[i]) - pose_.linear() * D(sensor.normals[i])).norm(), 1e-5);
    EXPECT_FLOAT_EQ(world.ranges[i], sensor.ranges[i]);
    EXPECT_FLOAT_EQ(world.intensities[i], sensor.intensities[i]);
  }
}

class BunnyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bunny_ = test::ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply");
    ASSERT_EQ(bunny_.vertices.size(), 8171u);
    ASSERT_EQ(bunny_.triangles.size(), 16301u);
  }

  static TriangleMesh InWorld(const TriangleMesh& mesh, const Pose3& world_from_object) {
    TriangleMesh world = mesh;
    for (auto& v : world.vertices) v = (world_from_object * v.cast<double>()).cast<float>();
    return world;
  }

  TriangleMesh bunny_;
};

TEST_F(BunnyTest, PointsLieOnTheMesh) {
  const Pose3 placed = Eigen::Translation3d(0.5, 0.0, 0.0) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ());
  auto scene = BuildScene({Instance(bunny_, 11, placed)});
  const Eigen::Vector3d middle = placed * Eigen::Vector3d(-0.017, 0.11, 0.0);
  const Pose3 pose = LookAt(middle + Eigen::Vector3d(0.05, -0.4, 0.05), middle);
  const sensor::PinholeCamera camera = sensor::CameraFromFov(160, 120, 40.0, 0.05, 2.0);

  const PointCloud cloud = ScanOk(*scene, camera, pose, ScanFrame::kWorld);
  ASSERT_GT(cloud.size(), 2000u);
  const TriangleMesh world = InWorld(bunny_, placed);
  const size_t step = cloud.size() / 150;
  for (size_t i = 0; i < cloud.size(); i += step) {
    EXPECT_LE(test::DistanceToMesh(D(cloud.positions[i]), world), 1e-5) << "point " << i;
  }
  for (uint32_t id : cloud.instance_ids) ASSERT_EQ(id, 11u);
}

TEST_F(BunnyTest, TwoInstancesGetTheirOwnIds) {
  const Pose3 left = Pose3(Eigen::Translation3d(0.0, 0.0, 0.0));
  const Pose3 right = Eigen::Translation3d(0.17, 0.0, 0.0) * Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY());
  auto scene = BuildScene({Instance(bunny_, 21, left), Instance(bunny_, 22, right)});
  const Eigen::Vector3d middle(0.07, 0.11, 0.0);
  const Pose3 pose = LookAt(middle + Eigen::Vector3d(0.0, 0.02, 0.6), middle);
  const sensor::PinholeCamera camera = sensor::CameraFromFov(160, 120, 45.0, 0.05, 2.0);

  const PointCloud cloud = ScanOk(*scene, camera, pose, ScanFrame::kWorld);
  ASSERT_GT(cloud.size(), 2000u);
  const std::set<uint32_t> ids(cloud.instance_ids.begin(), cloud.instance_ids.end());
  EXPECT_EQ(ids, (std::set<uint32_t>{21, 22}));
  const TriangleMesh world_left = InWorld(bunny_, left), world_right = InWorld(bunny_, right);
  const size_t step = cloud.size() / 100;
  for (size_t i = 0; i < cloud.size(); i += step) {
    const TriangleMesh& own = cloud.instance_ids[i] == 21 ? world_left : world_right;
    EXPECT_LE(test::DistanceToMesh(D(cloud.positions[i]), own), 1e-5) << "point " << i;
  }
}

TEST(ScannerTest, EmptySceneHitsNothing) {
  auto scene = BuildScene({});
  const sensor::PinholeCamera camera = sensor::CameraFromFov(40, 30, 60.0, 0.1, 10.0);
  ScanStats stats;
  const PointCloud cloud = ScanOk(*scene, camera, Pose3::Identity(), ScanFrame::kWorld, kFieldsAll, &stats);
  EXPECT_EQ(cloud.size(), 0u);
  EXPECT_EQ(stats.rays, 1200u);
  EXPECT_EQ(stats.points, 0u);
  EXPECT_EQ(stats.min_range, 0.0);
  EXPECT_EQ(stats.max_range, 0.0);
}

TEST(ScannerTest, CancelledBeforeItStarts) {
  auto scene = BuildScene({Instance(test::MakeIcosphere(Eigen::Vector3d(0, 0, 3), 1.0, 2), 1)});
  const std::atomic<bool> cancel{true};
  ScanOptions options;
  options.cancel = &cancel;
  auto cloud = Scan(*scene, sensor::CameraFromFov(64, 48, 60.0, 0.1, 10.0), Pose3::Identity(), options);
  ASSERT_FALSE(cloud.ok());
  EXPECT_EQ(cloud.status().code(), StatusCode::kCancelled);
  EXPECT_EQ(cloud.status().message(), "scan cancelled");
}

TEST(ScannerTest, RejectsBadCameraAndPose) {
  auto scene = BuildScene({});
  sensor::PinholeCamera camera = sensor::CameraFromFov(64, 48, 60.0, 0.1, 10.0);
  camera.width = 0;
  EXPECT_EQ(Scan(*scene, camera, Pose3::Identity(), {}).status().code(), StatusCode::kInvalidArgument);
  camera = sensor::CameraFromFov(64, 48, 60.0, 5.0, 5.0);
  const Status near_far = Scan(*scene, camera, Pose3::Identity(), {}).status();
  EXPECT_EQ(near_far.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(near_far.message().find("near must be less than far"), std::string::npos) << near_far.message();
  Pose3 pose = Pose3::Identity();
  pose.translation().y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Scan(*scene, sensor::CameraFromFov(8, 8, 60.0, 0.1, 1.0), pose, {}).status().code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace vscan::raycast
