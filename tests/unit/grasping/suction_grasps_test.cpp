#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "grasp_checks.h"
#include "grasp_shapes.h"
#include "grasping/grasp_generation.h"
#include "vscan_test/meshes.h"

namespace vscan::grasping {
namespace {

// The box 40 x 30 x 20 mm.
const Eigen::Vector3d kBoxHi(0.04, 0.03, 0.02);

GraspOptions Dense() {
  GraspOptions o;
  o.max_grasps = 100000;
  o.candidates = 3000;
  o.surface_samples = 40000;
  return o;
}

std::vector<Grasp> Suction(const TriangleMesh& mesh, double diameter, GraspOptions options = Dense()) {
  SuctionCup cup;
  cup.diameter_m = diameter;
  auto grasps = GenerateGrasps(mesh, cup, options);
  EXPECT_TRUE(grasps.ok()) << grasps.status().ToString();
  return grasps.ok() ? *grasps : std::vector<Grasp>{};
}

// The box face a suction grasp sits on, as +-(axis + 1): the approach is minus its outward normal.
int FaceOf(const Grasp& g) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(std::abs(g.approach[axis]) - 1) < 1e-6) return g.approach[axis] < 0 ? axis + 1 : -(axis + 1);
  }
  return 0;
}

void ExpectWellFormedSuction(const std::vector<Grasp>& grasps) {
  testing::ExpectSortedRigidGrasps(grasps);
  for (const Grasp& g : grasps) {
    EXPECT_TRUE(g.part_from_tool.linear().col(2).isApprox(g.approach, 1e-12));
  }
}

TEST(SuctionGraspsTest, SmallCupSealsOnEveryBoxFaceAwayFromItsEdges) {
  const double diameter = 0.010, r = diameter / 2;
  const auto grasps = Suction(test::MakeBox({0, 0, 0}, kBoxHi), diameter);
  ExpectWellFormedSuction(grasps);
  std::set<int> faces;
  for (const Grasp& g : grasps) {
    const int face = FaceOf(g);
    ASSERT_NE(face, 0) << "approach not minus a face normal: " << g.approach.transpose();
    faces.insert(face);
    const Eigen::Vector3d c = g.part_from_tool.translation();
    const int axis = std::abs(face) - 1;
    EXPECT_NEAR(c[axis], face > 0 ? kBoxHi[axis] : 0, 1e-6);  // on that face
    for (int other = 0; other < 3; ++other) {
      if (other == axis) continue;
      // At least a cup radius from the face's edges, within the flatness and sampling tolerance.
      EXPECT_GE(c[other], r - 0.001) << "face " << face;
      EXPECT_LE(c[other], kBoxHi[other] - r + 0.001) << "face " << face;
    }
  }
  EXPECT_EQ(faces, (std::set<int>{-3, -2, -1, 1, 2, 3}));
}

TEST(SuctionGraspsTest, CupSealsOnlyOnFacesItFits) {
  const TriangleMesh box = test::MakeBox({0, 0, 0}, kBoxHi);
  // 25 mm fits the 40 x 30 faces only (the others are 20 mm across in one direction).
  const auto grasps = Suction(box, 0.025);
  ASSERT_FALSE(grasps.empty());
  std::set<int> faces;
  for (const Grasp& g : grasps) faces.insert(FaceOf(g));
  EXPECT_EQ(faces, (std::set<int>{-3, 3}));
  // 50 mm is wider than every face.
  EXPECT_TRUE(Suction(box, 0.050).empty());
}

TEST(SuctionGraspsTest, CurvedSphereRefusesALargeCup) {
  const TriangleMesh sphere = test::MakeUvSphere(0.02, 32, 64);
  EXPECT_TRUE(Suction(sphere, 0.030).empty());
}

TEST(SuctionGraspsTest, NoCupOverlapsTheHoleOfAPlate) {
  // 60 x 60 x 3 mm with a 12 x 12 mm hole; a 10 mm cup.
  const TriangleMesh plate = testing::MakePlateWithHole(0.030, 0.006, 0.003);
  ASSERT_GT(plate.SignedVolume(), 0);
  const double r = 0.005;
  const auto grasps = Suction(plate, 2 * r);
  ASSERT_FALSE(grasps.empty());
  for (const Grasp& g : grasps) {
    const Eigen::Vector3d c = g.part_from_tool.translation();
    EXPECT_NEAR(std::abs(g.approach.z()), 1, 1e-6);
    // Distance in the plate's plane from the hole's square.
    const double from_hole = (c.head<2>().cwiseAbs().array() - 0.006).cwiseMax(0).matrix().norm();
    EXPECT_GE(from_hole, r - 0.001) << c.transpose();
    EXPECT_LE(std::max(std::abs(c.x()), std::abs(c.y())), 0.030 - r + 0.001) << c.transpose();
  }
}

TEST(SuctionGraspsTest, TheBestOfAPlateLieOnBothItsFaces) {
  // Both faces are equally flat: their grasps tie, and the 30 best are drawn from both.
  const TriangleMesh plate = testing::MakePlateWithHole(0.030, 0.006, 0.003);
  GraspOptions options;
  options.max_grasps = 30;
  const auto grasps = GenerateGrasps(plate, SuctionCup{0.010, 0.01, 10, 0.9}, options);
  ASSERT_TRUE(grasps.ok());
  ASSERT_EQ(grasps->size(), 30u);
  size_t up = 0;
  for (const Grasp& g : *grasps) up += g.approach.z() > 0;
  EXPECT_GT(up, 5u);
  EXPECT_LT(up, 25u);
}

TEST(SuctionGraspsTest, SameSeedSameGrasps) {
  const TriangleMesh box = test::MakeBox({0, 0, 0}, kBoxHi);
  GraspOptions options;
  options.seed = 7;
  const auto a = Suction(box, 0.010, options), b = Suction(box, 0.010, options);
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].part_from_tool.matrix(), b[i].part_from_tool.matrix());
    EXPECT_EQ(a[i].quality, b[i].quality);
  }
  options.seed = 8;
  const auto c = Suction(box, 0.010, options);
  ASSERT_FALSE(c.empty());
  EXPECT_NE(a.front().part_from_tool.translation(), c.front().part_from_tool.translation());
}

TEST(SuctionGraspsTest, MaxGraspsKeepsTheBest) {
  GraspOptions options = Dense();
  options.max_grasps = 5;
  const auto few = Suction(test::MakeBox({0, 0, 0}, kBoxHi), 0.010, options);
  const auto all = Suction(test::MakeBox({0, 0, 0}, kBoxHi), 0.010);
  ASSERT_EQ(few.size(), 5u);
  ASSERT_GT(all.size(), 5u);
  for (size_t i = 0; i < few.size(); ++i) {
    EXPECT_EQ(few[i].part_from_tool.matrix(), all[i].part_from_tool.matrix());
  }
}

}  // namespace
}  // namespace vscan::grasping
