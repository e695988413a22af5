#include "multiview_views.h"

#include <memory>
#include <random>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "icp_test_util.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan_test/ascii_ply.h"

namespace vscan::registration::testing {
namespace {

struct Bunny {
  std::shared_ptr<const raycast::RaycastScene> scene;
  Eigen::Vector3d centre;
};

const Bunny& LoadBunny() {
  static const Bunny bunny = [] {
    auto mesh = std::make_shared<const TriangleMesh>(
        test::ReadAsciiPly(std::string(VSCAN_DATA_DIR) + "/meshes/bunny/bunny_zipper_res2.ply"));
    Eigen::AlignedBox3d box;
    for (const auto& v : mesh->vertices) box.extend(v.cast<double>());
    raycast::SceneInstance instance;
    instance.mesh = mesh;
    auto scene = raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1));
    EXPECT_TRUE(scene.ok()) << scene.status().ToString();
    return Bunny{scene.ok() ? *scene : nullptr, box.center()};
  }();
  return bunny;
}

}  // namespace

Eigen::Vector3d BunnyCentre() { return LoadBunny().centre; }

Pose3 ViewAround(double azimuth_deg, double elevation_deg, double distance) {
  const double a = azimuth_deg * kDeg, e = elevation_deg * kDeg;
  const Eigen::Vector3d direction(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a));
  const Eigen::Vector3d centre = BunnyCentre();
  auto pose = PoseFromLookAt(centre + distance * direction, centre, Eigen::Vector3d::UnitY(), "view");
  EXPECT_TRUE(pose.ok()) << pose.status().ToString();
  return pose.ok() ? *pose : Pose3::Identity();
}

BunnyView ScanBunny(const Pose3& model_from_sensor, double fov_deg, double noise_sigma, uint32_t seed) {
  const sensor::PinholeCamera camera = sensor::CameraFromFov(320, 240, fov_deg, 0.05, 2.0);
  raycast::ScanOptions options;
  options.fields = kFieldPosition;
  options.frame = raycast::ScanFrame::kSensor;
  auto cloud = raycast::Scan(*LoadBunny().scene, camera, model_from_sensor, options);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  BunnyView view;
  view.model_from_sensor = model_from_sensor;
  if (!cloud.ok()) return view;
  view.points = std::move(cloud->positions);
  if (noise_sigma > 0.0) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> noise(0.0f, static_cast<float>(noise_sigma));
    for (auto& p : view.points) p += Eigen::Vector3f(noise(rng), noise(rng), noise(rng));
  }
  return view;
}

Pose3 RandomError(double angle_deg, double shift, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  const Eigen::Vector3d direction = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  Pose3 error = RotationAboutLine(BunnyCentre(), axis, angle_deg * kDeg);
  error.translation() += shift * direction;
  return error;
}

double CentreErrorMm(const Pose3& estimate, const Pose3& truth) {
  const Eigen::Vector3d c = BunnyCentre();
  return (estimate * (truth.inverse() * c) - c).norm() * 1000.0;
}

}  // namespace vscan::registration::testing
