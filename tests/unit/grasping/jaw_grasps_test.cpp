#include <cmath>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "grasp_checks.h"
#include "grasp_shapes.h"
#include "grasping/grasp_generation.h"
#include "vscan_test/meshes.h"

namespace vscan::grasping {
namespace {

std::vector<Grasp> Jaws(const TriangleMesh& mesh, double max_opening, uint64_t seed = 1) {
  ParallelJaws jaws;
  jaws.min_opening_m = 0.002;
  jaws.max_opening_m = max_opening;
  jaws.finger_width_m = 0.008;
  jaws.finger_depth_m = 0.008;
  jaws.max_friction_angle_deg = 15;
  GraspOptions options;
  options.max_grasps = 100000;
  options.candidates = 1500;
  options.seed = seed;
  auto grasps = GenerateGrasps(mesh, jaws, options);
  EXPECT_TRUE(grasps.ok()) << grasps.status().ToString();
  return grasps.ok() ? *grasps : std::vector<Grasp>{};
}

Eigen::Vector3d Axis(const Grasp& g) { return g.part_from_tool.linear().col(1); }

void ExpectWellFormedJaws(const std::vector<Grasp>& grasps) {
  testing::ExpectSortedRigidGrasps(grasps);
  for (const Grasp& g : grasps) {
    EXPECT_NEAR(g.part_from_tool.linear().determinant(), 1, 1e-9);
    EXPECT_NEAR(g.approach.dot(Axis(g)), 0, 1e-9);  // approach perpendicular to the squeeze
  }
}

TEST(JawGraspsTest, BoxIsGraspedOnlyAcrossDimensionsTheJawsOpenTo) {
  // 40 x 30 x 20 mm with a 35 mm opening: across y (30) and z (20), never across x (40).
  const auto grasps = Jaws(test::MakeBox({0, 0, 0}, {0.04, 0.03, 0.02}), 0.035);
  ExpectWellFormedJaws(grasps);
  std::set<int> axes;
  for (const Grasp& g : grasps) {
    const Eigen::Vector3d a = Axis(g).cwiseAbs();
    Eigen::Index axis;
    ASSERT_NEAR(a.maxCoeff(&axis), 1, 1e-6);
    axes.insert(int(axis));
    EXPECT_NEAR(g.opening_m, axis == 1 ? 0.03 : 0.02, 1e-5);
    EXPECT_NEAR(g.quality, 1, 1e-6);  // parallel faces: no friction needed
  }
  EXPECT_EQ(axes, (std::set<int>{1, 2}));
}

TEST(JawGraspsTest, CylinderIsGraspedAcrossItsDiameter) {
  // 20 mm across, 60 mm long: the ends are beyond a 35 mm opening.
  const double radius = 0.010;
  const int segments = 48;
  const auto grasps = Jaws(testing::MakeCylinder(radius, 0.060, segments), 0.035);
  ExpectWellFormedJaws(grasps);
  ASSERT_GT(grasps.size(), 10u);
  for (const Grasp& g : grasps) {
    EXPECT_NEAR(Axis(g).z(), 0, 1e-6);
    EXPECT_LE(g.opening_m, 2 * radius + 1e-6);
    EXPECT_GE(g.opening_m, 2 * radius * std::cos(std::numbers::pi / segments) - 1e-6);
    EXPECT_LT(g.part_from_tool.translation().head<2>().norm(), 0.001);  // on the axis
  }
}

TEST(JawGraspsTest, SphereIsGraspedAcrossItsDiameter) {
  const auto grasps = Jaws(test::MakeUvSphere(0.02, 32, 64), 0.050);
  ExpectWellFormedJaws(grasps);
  ASSERT_GT(grasps.size(), 10u);
  for (const Grasp& g : grasps) {
    EXPECT_NEAR(g.opening_m, 0.04, 0.001);
    EXPECT_LT(g.part_from_tool.translation().norm(), 0.0015);  // faceted: face normals miss the centre slightly
  }
  // Too small an opening: nothing.
  EXPECT_TRUE(Jaws(test::MakeUvSphere(0.02, 32, 64), 0.030).empty());
}

TEST(JawGraspsTest, FingerThatWouldHitANeighbouringBlockIsRefused) {
  // A 10 mm block with another 4 mm beside it: the finger closing onto the near face sweeps
  // (35 - 10) / 2 = 12.5 mm outwards and meets it. Moved 50 mm away, the 10 mm grasps come back.
  const TriangleMesh block = test::MakeBox({0, 0, 0}, {0.010, 0.030, 0.020});
  const auto count_across_x = [](const std::vector<Grasp>& grasps) {
    size_t n = 0;
    for (const Grasp& g : grasps) n += std::abs(g.opening_m - 0.010) < 1e-5;
    return n;
  };
  const auto near = Jaws(testing::Join(block, test::MakeBox({0.014, 0, 0}, {0.024, 0.030, 0.020})), 0.035);
  const auto far = Jaws(testing::Join(block, test::MakeBox({0.060, 0, 0}, {0.070, 0.030, 0.020})), 0.035);
  EXPECT_EQ(count_across_x(near), 0u);
  EXPECT_GT(count_across_x(far), 10u);
  EXPECT_GT(near.size(), 10u);  // across y and z both blocks are still graspable
}

TEST(JawGraspsTest, SameSeedSameGrasps) {
  const TriangleMesh box = test::MakeBox({0, 0, 0}, {0.04, 0.03, 0.02});
  const auto a = Jaws(box, 0.035, 3), b = Jaws(box, 0.035, 3);
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].part_from_tool.matrix(), b[i].part_from_tool.matrix());
    EXPECT_EQ(a[i].opening_m, b[i].opening_m);
  }
}

}  // namespace
}  // namespace vscan::grasping
