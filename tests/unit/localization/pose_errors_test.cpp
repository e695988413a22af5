#include "localization/pose_errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "localization/part_symmetries.h"
#include "part_shapes.h"
#include "vscan_test/meshes.h"

namespace vscan::localization {
namespace {

using testing::CubeRotations;
using testing::CubeWithFaceCentres;
using testing::Rings;

Pose3 SomePose() {
  Pose3 pose = RotationAboutLine(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1, -2, 0.5), 0.7);
  pose.translation() += Eigen::Vector3d(0.4, -0.1, 0.9);
  return pose;
}

TEST(Diameter, OfABoxIsItsSpaceDiagonal) {
  const TriangleMesh box = test::MakeBox(Eigen::Vector3d(-0.05, 0, 0.2), Eigen::Vector3d(0.05, 0.2, 0.5));
  EXPECT_NEAR(Diameter(box.vertices), std::sqrt(0.1 * 0.1 + 0.2 * 0.2 + 0.3 * 0.3), 1e-7);
}

TEST(Diameter, OfOneVertexIsZero) {
  const std::vector<Eigen::Vector3f> one{Eigen::Vector3f(1, 2, 3)};
  EXPECT_EQ(Diameter(one), 0.0);
}

// Every pair compared, as BOP's calc_pts_diameter does.
double BruteForceDiameter(const std::vector<Eigen::Vector3f>& points) {
  double best = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      best = std::max(best, (points[i].cast<double>() - points[j].cast<double>()).squaredNorm());
    }
  }
  return std::sqrt(best);
}

TEST(Diameter, EqualsEveryPairComparedOnSpheresBoxesAndRods) {
  std::mt19937 rng(5);
  std::normal_distribution<float> gauss;
  std::uniform_real_distribution<float> uniform(-1, 1);
  for (int shape = 0; shape < 4; ++shape) {
    std::vector<Eigen::Vector3f> points(6000);
    for (Eigen::Vector3f& p : points) {
      const Eigen::Vector3f g(gauss(rng), gauss(rng), gauss(rng));
      if (shape == 0) p = g.normalized() * 0.05f;                                       // a sphere's surface
      if (shape == 1) p = Eigen::Vector3f(uniform(rng), 0.5f * uniform(rng), 0.1f * uniform(rng));  // a slab
      if (shape == 2) p = Eigen::Vector3f(0.002f * g.x(), 0.002f * g.y(), 0.3f * uniform(rng));    // a thin pin
      if (shape == 3) p = Eigen::Vector3f(0.01f * std::round(10 * uniform(rng)), 0, 0);  // many equal points
    }
    EXPECT_EQ(Diameter(points), BruteForceDiameter(points)) << "shape " << shape;
  }
}

TEST(PoseErrors, IdentityGivesZero) {
  const std::vector<Eigen::Vector3f> cube = CubeWithFaceCentres(0.05);
  const Pose3 pose = SomePose();
  EXPECT_NEAR(AddError(cube, pose, pose), 0, 1e-12);
  EXPECT_NEAR(AddSError(cube, pose, pose), 0, 1e-7);
  EXPECT_NEAR(MssdError(cube, pose, pose, {}), 0, 1e-12);
}

TEST(PoseErrors, TranslationByDGivesDForAll) {
  // Vertices 10 cm apart and a shift of 4 mm: each vertex's nearest true vertex is its own.
  const std::vector<Eigen::Vector3f> cube = CubeWithFaceCentres(0.05);
  const Pose3 truth = SomePose();
  const double d = 0.004;
  Pose3 estimate = truth;
  estimate.translation() += d * Eigen::Vector3d(2, -1, 2).normalized();
  EXPECT_NEAR(AddError(cube, estimate, truth), d, 1e-12);
  EXPECT_NEAR(AddSError(cube, estimate, truth), d, 1e-7);
  EXPECT_NEAR(MssdError(cube, estimate, truth, {}), d, 1e-12);
}

TEST(PoseErrors, AddSRunsFromTheTrueVerticesToTheNearestEstimatedOnes) {
  // Vertices at 0, 1 and 5 cm on the part's x axis, the estimate 4 cm along it: at 4, 5 and 9 cm.
  // From the true vertices (BOP's adi): 4, 3 and 0 cm, mean 7/3 cm. The other way round, from the
  // estimated ones: 1, 0 and 4 cm, mean 5/3 cm.
  const std::vector<Eigen::Vector3f> line{{0, 0, 0}, {0.01f, 0, 0}, {0.05f, 0, 0}};
  const Pose3 truth = SomePose();
  const Pose3 estimate = truth * Eigen::Translation3d(0.04, 0, 0);
  EXPECT_NEAR(AddSError(line, estimate, truth), 0.07 / 3, 1e-8);
  EXPECT_NEAR(AddSError(line, truth, estimate), 0.05 / 3, 1e-8);
  EXPECT_NEAR(AddError(line, estimate, truth), 0.04, 1e-12);
}

TEST(PoseErrors, TurnAboutTheSymmetryAxisCostsOnlyAdd) {
  // 36 vertices per ring, turned by 40 degrees: a multiple of both the ring's 10 degrees (so each
  // vertex lands on another one) and BOP's step 2 pi / 315 (35 steps).
  const double radius = 0.03;
  const std::vector<Eigen::Vector3f> rings = Rings(radius, 36, {0.0, 0.02, 0.05});
  const Eigen::Vector3d axis_point(0, 0, 0);
  PartSymmetries symmetries;
  symmetries.continuous.push_back({Eigen::Vector3d::UnitZ(), axis_point});
  const std::vector<Pose3> transforms = SymmetryTransforms(symmetries);
  ASSERT_EQ(transforms.size(), 315u);

  const Pose3 truth = SomePose();
  const double angle = 40 * std::numbers::pi / 180;
  const Pose3 estimate = truth * RotationAboutLine(axis_point, Eigen::Vector3d::UnitZ(), angle);
  EXPECT_NEAR(MssdError(rings, estimate, truth, transforms), 0, 1e-7);
  EXPECT_NEAR(AddSError(rings, estimate, truth), 0, 1e-6);
  // Every vertex moves along a chord of its ring.
  EXPECT_NEAR(AddError(rings, estimate, truth), 2 * radius * std::sin(angle / 2), 1e-9);
  // Without the symmetry MSSD sees the same chord.
  EXPECT_NEAR(MssdError(rings, estimate, truth, {}), 2 * radius * std::sin(angle / 2), 1e-9);
}

TEST(PoseErrors, ContinuousSymmetryOffTheOriginTurnsAboutItsOwnLine) {
  const Eigen::Vector3d centre(0.2, -0.1, 0);
  std::vector<Eigen::Vector3f> rings = Rings(0.03, 36, {0.0, 0.04});
  for (auto& v : rings) v += centre.cast<float>();
  PartSymmetries symmetries;
  symmetries.continuous.push_back({Eigen::Vector3d(0, 0, 2), centre});
  const Pose3 truth = SomePose();
  const Pose3 estimate = truth * RotationAboutLine(centre, Eigen::Vector3d::UnitZ(), 80 * std::numbers::pi / 180);
  EXPECT_NEAR(MssdError(rings, estimate, truth, SymmetryTransforms(symmetries)), 0, 1e-7);
  EXPECT_GT(AddError(rings, estimate, truth), 0.03);
}

TEST(PoseErrors, CubeTurnsOfItsRotationGroupHaveNoMssd) {
  const double half = 0.05;
  const std::vector<Eigen::Vector3f> cube = CubeWithFaceCentres(half);
  PartSymmetries symmetries;
  symmetries.discrete = CubeRotations();
  const std::vector<Pose3> transforms = SymmetryTransforms(symmetries);
  ASSERT_EQ(transforms.size(), 24u);
  const Pose3 truth = SomePose();
  size_t with_add = 0;
  for (const Pose3& s : transforms) {
    const Pose3 estimate = truth * s;
    EXPECT_NEAR(MssdError(cube, estimate, truth, transforms), 0, 1e-9);
    EXPECT_NEAR(AddSError(cube, estimate, truth), 0, 1e-6);
    if (AddError(cube, estimate, truth) > 0.01) ++with_add;
  }
  EXPECT_EQ(with_add, 23u);  // all but the identity

  // 45 degrees about z is half way between two symmetries: each corner moves by a chord of 45
  // degrees on its circle of radius half * sqrt(2) about z.
  const Pose3 estimate = truth * RotationAboutLine(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                                                   std::numbers::pi / 4);
  EXPECT_NEAR(MssdError(cube, estimate, truth, transforms),
              2 * half * std::sqrt(2.0) * std::sin(std::numbers::pi / 8), 1e-7);
}

TEST(SymmetryTransforms, IdentityComesFirstAndOnce) {
  PartSymmetries symmetries;
  symmetries.discrete = {Pose3::Identity(),
                         RotationAboutLine(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), std::numbers::pi)};
  const std::vector<Pose3> transforms = SymmetryTransforms(symmetries);
  ASSERT_EQ(transforms.size(), 2u);
  EXPECT_TRUE(transforms[0].isApprox(Pose3::Identity()));
  // Discrete times continuous: 2 x 315.
  symmetries.continuous.push_back({Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero()});
  EXPECT_EQ(SymmetryTransforms(symmetries).size(), 630u);
}

}  // namespace
}  // namespace vscan::localization
