// Projector shadows and field of view against analytic predictions (similar triangles).

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "raycast/scanner.h"
#include "sensor/structured_light_visibility.h"

namespace vscan::sensor {
namespace {

constexpr double kPlaneDepth = 1.0;
constexpr double kPostDepth = 0.5;
constexpr double kPostX0 = 0.05, kPostX1 = 0.10;

// A sensor pose that is not axis-aligned, so the world/sensor transform is exercised.
const Pose3 kWorldFromSensor = [] {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, -1.2, 0.8);
  return pose;
}();

// Rectangle [x0, x1] x [y0, y1] at depth z in the sensor frame, placed in the world.
TriangleMesh Rectangle(double x0, double x1, double y0, double y1, double z) {
  TriangleMesh mesh;
  for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) {
    mesh.vertices.push_back((kWorldFromSensor * Eigen::Vector3d(x, y, z)).cast<float>());
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

std::shared_ptr<const raycast::RaycastScene> Scene(std::vector<TriangleMesh> meshes) {
  std::vector<raycast::SceneInstance> instances;
  for (auto& mesh : meshes) {
    raycast::SceneInstance instance;
    instance.mesh = std::make_shared<const TriangleMesh>(std::move(mesh));
    instance.instance_id = static_cast<uint32_t>(instances.size() + 1);
    instances.push_back(std::move(instance));
  }
  auto scene = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  return scene.ok() ? *scene : nullptr;
}

struct ClassifiedScan {
  PointCloud cloud;
  std::vector<ProjectorVisibility> visibility;
};

ClassifiedScan ScanAndClassify(const raycast::RaycastScene& scene, const StructuredLight& sl) {
  raycast::ScanOptions options;
  options.fields = kFieldsAll;
  options.frame = raycast::ScanFrame::kSensor;
  auto cloud = raycast::Scan(scene, sl.camera, kWorldFromSensor, options);
  EXPECT_TRUE(cloud.ok()) << cloud.status().ToString();
  ClassifiedScan out{std::move(cloud).value(), {}};
  out.visibility = ProjectorVisibilityOf(scene, kWorldFromSensor, sl, out.cloud.positions);
  return out;
}

StructuredLight VisibilityScanner(double baseline_x) {
  StructuredLight sl;
  sl.camera = CameraFromFov(240, 120, 60.0, 0.05, 10.0);
  sl.projector_offset = {baseline_x, 0, 0};
  sl.projector_hfov_deg = 150;  // wide enough to light the whole view: only shadows remain
  sl.projector_vfov_deg = 150;
  EXPECT_TRUE(ValidateStructuredLight(sl, "sl").ok());
  return sl;
}

enum class Expect { kLit, kShadowed, kEdge };

// What pixel column u sees: the post (lit), or the plane, shadowed where the segment from the projector
// at (b, 0, 0) crosses the post's depth within [x0, x1]: X in b + ([x0, x1] - b) * plane / post depth.
Expect Predict(const StructuredLight& sl, uint32_t u) {
  const double b = sl.projector_offset.x();
  const double slope = (u + 0.5 - sl.camera.cx) / sl.camera.fx;
  const double x_at_post = slope * kPostDepth;
  const double post_pixel = kPostDepth / sl.camera.fx;
  if (std::abs(x_at_post - kPostX0) < post_pixel || std::abs(x_at_post - kPostX1) < post_pixel) return Expect::kEdge;
  if (x_at_post > kPostX0 && x_at_post < kPostX1) return Expect::kLit;
  const double x = slope * kPlaneDepth;
  const double scale = kPlaneDepth / kPostDepth;
  const double lo = std::min(b + (kPostX0 - b) * scale, b + (kPostX1 - b) * scale);
  const double hi = std::max(b + (kPostX0 - b) * scale, b + (kPostX1 - b) * scale);
  const double plane_pixel = kPlaneDepth / sl.camera.fx;
  if (std::abs(x - lo) < plane_pixel || std::abs(x - hi) < plane_pixel) return Expect::kEdge;
  return x > lo && x < hi ? Expect::kShadowed : Expect::kLit;
}

// Checks every pixel against the prediction; returns the mean column of the shadowed pixels.
double CheckShadow(double baseline_x) {
  const StructuredLight sl = VisibilityScanner(baseline_x);
  const auto scene = Scene({Rectangle(-2, 2, -2, 2, kPlaneDepth), Rectangle(kPostX0, kPostX1, -2, 2, kPostDepth)});
  const ClassifiedScan scan = ScanAndClassify(*scene, sl);
  EXPECT_EQ(scan.cloud.size(), sl.camera.pixel_count());
  size_t shadowed = 0, lit = 0, checked = 0;
  double shadow_column_sum = 0;
  for (size_t i = 0; i < scan.cloud.size(); ++i) {
    const uint32_t u = scan.cloud.pixels[i] % sl.camera.width;
    const ProjectorVisibility got = scan.visibility[i];
    EXPECT_NE(got, ProjectorVisibility::kUnlit) << "pixel " << scan.cloud.pixels[i];
    if (got == ProjectorVisibility::kShadowed) {
      ++shadowed;
      shadow_column_sum += u;
    } else {
      ++lit;
    }
    const Expect expected = Predict(sl, u);
    if (expected == Expect::kEdge) continue;
    ++checked;
    EXPECT_EQ(got == ProjectorVisibility::kShadowed, expected == Expect::kShadowed)
        << "baseline " << baseline_x << " column " << u << " row " << scan.cloud.pixels[i] / sl.camera.width;
  }
  EXPECT_GT(shadowed, 0u);
  EXPECT_GT(lit, shadowed);
  EXPECT_GT(checked, scan.cloud.size() * 9 / 10);
  return shadowed ? shadow_column_sum / shadowed : 0;
}

TEST(ProjectorShadow, MatchesSimilarTrianglesAndFollowsTheBaseline) {
  // Projector on the right (+x): the post's shadow falls on its left; swapped, on its right.
  const StructuredLight sl = VisibilityScanner(0.1);
  const double post_left_column = kPostX0 / kPostDepth * sl.camera.fx + sl.camera.cx;
  const double post_right_column = kPostX1 / kPostDepth * sl.camera.fx + sl.camera.cx;
  const double right = CheckShadow(0.1);
  const double left = CheckShadow(-0.1);
  EXPECT_LT(right, post_left_column);
  EXPECT_GT(left, post_right_column);
}

TEST(ProjectorShadow, NothingIsShadowedWithoutAnOccluder) {
  const StructuredLight sl = VisibilityScanner(0.2);
  const auto scene = Scene({Rectangle(-2, 2, -2, 2, kPlaneDepth)});
  const ClassifiedScan scan = ScanAndClassify(*scene, sl);
  ASSERT_EQ(scan.cloud.size(), sl.camera.pixel_count());
  EXPECT_TRUE(std::all_of(scan.visibility.begin(), scan.visibility.end(),
                          [](ProjectorVisibility v) { return v == ProjectorVisibility::kLit; }));
}

TEST(ProjectorField, RowsOutsideANarrowVerticalFieldAreUnlit) {
  for (const double convergence : {0.0, 0.8}) {
    StructuredLight sl = VisibilityScanner(0.1);
    sl.projector_vfov_deg = 10;
    sl.convergence_distance = convergence;
    const auto scene = Scene({Rectangle(-2, 2, -2, 2, kPlaneDepth)});
    const ClassifiedScan scan = ScanAndClassify(*scene, sl);
    ASSERT_EQ(scan.cloud.size(), sl.camera.pixel_count());
    // The projector sits at y = 0 and turns only about y, so the plane at depth 1 is lit where
    // |y| <= z_projector * tan(5 deg), z_projector being the point's depth along the projector axis.
    const Pose3 projector_from_sensor = SensorFromProjector(sl).inverse();
    const double half_tan = std::tan(5.0 * std::numbers::pi / 180.0);
    const double row_height = kPlaneDepth / sl.camera.fy;
    size_t unlit = 0, lit = 0;
    for (size_t i = 0; i < scan.cloud.size(); ++i) {
      const Eigen::Vector3d p = scan.cloud.positions[i].cast<double>();
      const double limit = (projector_from_sensor * p).z() * half_tan;
      const ProjectorVisibility got = scan.visibility[i];
      ASSERT_NE(got, ProjectorVisibility::kShadowed);
      (got == ProjectorVisibility::kUnlit ? unlit : lit)++;
      if (std::abs(std::abs(p.y()) - limit) < row_height) continue;
      EXPECT_EQ(got == ProjectorVisibility::kLit, std::abs(p.y()) < limit)
          << "row " << scan.cloud.pixels[i] / sl.camera.width << " convergence " << convergence;
    }
    // About 10 of the camera's 32 vertical degrees are lit.
    EXPECT_GT(unlit, lit);
    EXPECT_GT(lit, scan.cloud.size() / 5);
  }
}

TEST(ProjectorField, NonFinitePointsAreUnlit) {
  const StructuredLight sl = VisibilityScanner(0.1);
  const auto scene = Scene({});
  const std::vector<Eigen::Vector3f> points{{NAN, 0, 1}, {0, 0, 1}};
  const auto visibility = ProjectorVisibilityOf(*scene, kWorldFromSensor, sl, points);
  EXPECT_EQ(visibility[0], ProjectorVisibility::kUnlit);
  EXPECT_EQ(visibility[1], ProjectorVisibility::kLit);
}

}  // namespace
}  // namespace vscan::sensor
