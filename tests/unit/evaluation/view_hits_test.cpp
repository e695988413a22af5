#include "evaluation/view_hits.h"

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "evaluation/surface_sampling.h"
#include "evaluation/thinned_camera.h"
#include "spatial/kd_tree.h"
#include "vscan_test/meshes.h"

namespace vscan::evaluation {
namespace {

// A box with a ball in front of it: silhouettes, occlusion and surfaces at every incidence.
TriangleMesh Scene() {
  TriangleMesh mesh = test::MakeBox(Eigen::Vector3d(-0.1, -0.05, -0.15), Eigen::Vector3d(0.1, 0.05, 0.15));
  const TriangleMesh ball = test::MakeIcosphere(Eigen::Vector3d(0.15, 0.1, 0.05), 0.05, 3);
  const auto offset = static_cast<uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), ball.vertices.begin(), ball.vertices.end());
  for (const auto& t : ball.triangles) mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return mesh;
}

std::shared_ptr<const raycast::RaycastScene> Build(const TriangleMesh& mesh) {
  raycast::SceneInstance instance;
  instance.mesh = std::make_shared<const TriangleMesh>(mesh);
  auto scene = raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1));
  EXPECT_TRUE(scene.ok());
  return *scene;
}

Pose3 LookAt(const Eigen::Vector3d& eye) {
  auto pose = PoseFromLookAt(eye, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), "eye");
  EXPECT_TRUE(pose.ok());
  return *pose;
}

// The same question answered with a kd-tree over all of the view's hits.
SampleBits NearHitsByTree(const ViewHits& view, std::span<const Eigen::Vector3f> samples, double tau) {
  SampleBits seen(samples.size());
  const spatial::KdTree tree(view.hits);
  spatial::Neighbor nearest[1];
  const auto tau_sq = static_cast<float>(tau * tau);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (tree.Knn(samples[i], tau_sq, nearest) == 1) seen.Set(i);
  }
  return seen;
}

TEST(ViewHits, EachHitProjectsOntoItsPixelCentre) {
  const TriangleMesh mesh = Scene();
  const auto scene = Build(mesh);
  const sensor::PinholeCamera camera = ThinCamera(sensor::CameraFromFov(640, 480, 90, 0.05, 5), 2);
  const Pose3 pose = LookAt({0.5, -0.4, 0.3});
  const auto view = CastView(*scene, camera, pose, 90, nullptr);
  ASSERT_TRUE(view.ok()) << view.status().ToString();
  ASSERT_GT(view->hits.size(), 2'000u);
  const Pose3 sensor_from_frame = pose.inverse();
  size_t found = 0;
  for (uint32_t pixel = 0; pixel < view->hit_of_pixel.size(); ++pixel) {
    const int32_t hit = view->hit_of_pixel[pixel];
    if (hit < 0) continue;
    ++found;
    const Eigen::Vector3d p = sensor_from_frame * view->hits[static_cast<size_t>(hit)].cast<double>();
    EXPECT_NEAR(camera.fx * p.x() / p.z() + camera.cx, pixel % camera.width + 0.5, 0.01);
    EXPECT_NEAR(camera.fy * p.y() / p.z() + camera.cy, pixel / camera.width + 0.5, 0.01);
  }
  EXPECT_EQ(found, view->hits.size());
}

TEST(ViewHits, SamplesNearHitsMatchesAKdTreeOverAllHits) {
  const TriangleMesh mesh = Scene();
  const auto scene = Build(mesh);
  const std::vector<Eigen::Vector3f> samples = SampleSurface(mesh, 40'000, 8);
  // Wide and narrow views, near and far, fine and thinned images, small and large tau.
  const sensor::PinholeCamera wide = sensor::CameraFromFov(400, 300, 100, 0.05, 5);
  const sensor::PinholeCamera narrow = sensor::CameraFromFov(320, 240, 30, 0.05, 5);
  struct Case {
    sensor::PinholeCamera camera;
    Eigen::Vector3d eye;
    double tau;
  };
  const Case cases[] = {{wide, {0.4, -0.3, 0.2}, 0.002},          {ThinCamera(wide, 3), {0.4, -0.3, 0.2}, 0.02},
                        {narrow, {1.2, 0.3, -0.5}, 0.004},        {ThinCamera(narrow, 4), {-0.9, -0.6, 0.4}, 0.03},
                        {ThinCamera(wide, 2), {0.2, 0.35, 0.1}, 0.01}};
  for (const Case& c : cases) {
    const auto view = CastView(*scene, c.camera, LookAt(c.eye), 80, nullptr);
    ASSERT_TRUE(view.ok()) << view.status().ToString();
    ASSERT_GT(view->hits.size(), 100u);
    const SampleBits fast = SamplesNearHits(*view, samples, c.tau);
    const SampleBits tree = NearHitsByTree(*view, samples, c.tau);
    EXPECT_GT(tree.Count(), 500u) << c.eye.transpose();
    EXPECT_EQ(fast.Count(), tree.Count()) << c.eye.transpose();
    EXPECT_EQ(fast.CountNotIn(tree), 0u) << c.eye.transpose();
  }
}

TEST(ViewHits, NothingIsNearAViewThatHitsNothing) {
  const TriangleMesh mesh = Scene();
  const auto scene = Build(mesh);
  const std::vector<Eigen::Vector3f> samples = SampleSurface(mesh, 1'000, 2);
  // Looking away from the scene.
  const auto pose = PoseFromLookAt({1, 0, 0}, {2, 0, 0}, Eigen::Vector3d::UnitZ(), "eye");
  ASSERT_TRUE(pose.ok());
  const auto view = CastView(*scene, sensor::CameraFromFov(64, 64, 60, 0.05, 5), *pose, 80, nullptr);
  ASSERT_TRUE(view.ok());
  EXPECT_TRUE(view->hits.empty());
  EXPECT_EQ(SamplesNearHits(*view, samples, 0.05).Count(), 0u);
}

}  // namespace
}  // namespace vscan::evaluation

namespace vscan::evaluation {
namespace {

// A 1 m x 1 m plane facing the sensor 1 m away, lit by an emitter at the camera.
struct LitPlane {
  std::shared_ptr<const raycast::RaycastScene> scene =
      Build(test::MakeBox(Eigen::Vector3d(-0.5, -0.5, -0.01), Eigen::Vector3d(0.5, 0.5, 0)));
  sensor::PinholeCamera camera = sensor::CameraFromFov(64, 48, 40, 0.05, 5);
  Pose3 pose = *PoseFromLookAt({0, 0, 1}, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), "eye");

  MeasurableLight Light(const sensor::Material& material) const {
    MeasurableLight light;
    light.emitter.radiant_intensity_w_per_sr = 0.001;
    light.pixel.gain_e = 1e7;
    light.material = material;
    return light;
  }
};

sensor::Material Lambertian(double albedo) { return {albedo, 0.0, 1.0, 0.0}; }

TEST(ViewHits, UnderItsOwnLightOnlyTheSurfaceThatWouldDecodeIsSeen) {
  const LitPlane plane;
  const auto unlit = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr);
  ASSERT_TRUE(unlit.ok());
  ASSERT_EQ(unlit->hits.size(), plane.camera.pixel_count());
  // White: 0.9 / pi x 1e-3 / 1 m^2 x 1e7 = about 2900 e on the axis, an SNR above 50.
  const MeasurableLight white = plane.Light(Lambertian(0.9));
  const auto lit_white = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &white);
  ASSERT_TRUE(lit_white.ok());
  EXPECT_EQ(lit_white->hits.size(), unlit->hits.size());
  // Black at 0.003: about 9.5 e, an SNR near 1.7, under the bar of 5 everywhere.
  const MeasurableLight black = plane.Light(Lambertian(0.003));
  const auto lit_black = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &black);
  ASSERT_TRUE(lit_black.ok());
  EXPECT_TRUE(lit_black->hits.empty());
}

// Ambient light fills the well and adds noise but does not decode: a grey plane the emitter alone
// measures everywhere is lost under a strong ambient, as the scan itself loses it.
TEST(ViewHits, AStrongAmbientLightHidesWhatTheEmitterAloneWouldMeasure) {
  const LitPlane plane;
  // Grey 0.3: about 950 e from the emitter on the axis, an SNR near 30.
  MeasurableLight grey = plane.Light(Lambertian(0.3));
  grey.pixel.full_well_e = 1e9;
  const auto alone = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &grey);
  ASSERT_TRUE(alone.ok());
  EXPECT_EQ(alone->hits.size(), plane.camera.pixel_count());
  // 1 W/m^2 of ambient: 0.3 / pi x 1 x 1e7 = about 950 000 e of noise-only light, a noise near 975 e:
  // the emitter's 950 e stand under one sigma.
  grey.ambient_irradiance_w_per_m2 = 1.0;
  const auto drowned = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &grey);
  ASSERT_TRUE(drowned.ok());
  EXPECT_TRUE(drowned->hits.empty());
  // A weak ambient (1e-6 W/m^2, about 1 e) changes nothing.
  grey.ambient_irradiance_w_per_m2 = 1e-6;
  const auto faint = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &grey);
  ASSERT_TRUE(faint.ok());
  EXPECT_EQ(faint->hits.size(), plane.camera.pixel_count());
}

TEST(ViewHits, APolishedPlaneLosesOnlyTheSaturatedDiscAboutItsHighlight) {
  const LitPlane plane;
  MeasurableLight mirror = plane.Light({0.9, 1.0, 0.1, 0.04});
  mirror.pixel.full_well_e = 20000;
  const auto view = CastView(*plane.scene, plane.camera, plane.pose, 90, nullptr, &mirror);
  ASSERT_TRUE(view.ok());
  const uint32_t w = plane.camera.width, h = plane.camera.height;
  // The highlight sits on the axis (emitter and camera together): the centre is saturated, the
  // corners, far off the specular direction, are dark; the pixels in between decode.
  EXPECT_EQ(view->hit_of_pixel[(h / 2) * w + w / 2], -1);
  EXPECT_EQ(view->hit_of_pixel[0], -1);
  EXPECT_GT(view->hits.size(), 0u);
  EXPECT_LT(view->hits.size(), plane.camera.pixel_count());
}

}  // namespace
}  // namespace vscan::evaluation
