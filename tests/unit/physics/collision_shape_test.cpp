#include <gtest/gtest.h>

#include <cmath>

#include "fixture_parts.h"
#include "hull_support.h"
#include "machined_parts.h"
#include "physics/bin_fill.h"
#include "physics/bullet_fill_world.h"
#include "physics/part_geometry.h"

namespace vscan::physics {
namespace {

double ShapeOutsideBy(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& points) {
  return test::OutsideHullBy(p, points, 2000);
}

constexpr double kTolerance = 0.00005;

TEST(CollisionShape, ASimplifiedHullHoldsEveryHullVertexWithinTheTolerance) {
  for (const TriangleMesh& mesh : {test::Riser(), test::ManySidedPrism(), test::AngleBlock(1).mesh}) {
    const auto exact = ExactHull(mesh, Eigen::Vector3d::Zero());
    const auto simplified = SimplifiedHull(exact, kTolerance);
    EXPECT_LE(simplified.size(), exact.size());
    double worst = 0.0, worst_by_support = 0.0;
    for (const auto& p : exact) {
      worst = std::max(worst, DistanceOutsideHull(p, simplified));
      worst_by_support = std::max(worst_by_support, ShapeOutsideBy(p, simplified));
    }
    EXPECT_LE(worst, kTolerance);
    EXPECT_LE(worst_by_support, worst + 1e-9);  // the support bound never exceeds the distance
    // A prism's side sags between kept corners: a corner between two kept ones lies outside.
  }
}

TEST(CollisionShape, MachinedPartsHaveHullsOfHundredsOfVerticesThatTwentyFourPointsMissByMillimetres) {
  for (const TriangleMesh& mesh : {test::Riser(), test::ManySidedPrism()}) {
    const auto exact = ExactHull(mesh, Eigen::Vector3d::Zero());
    EXPECT_GE(exact.size(), 100u);
    EXPECT_LE(exact.size(), 300u);
    const auto farthest = FarthestPoints(exact, 24);
    double worst = 0.0;
    for (const auto& p : exact) worst = std::max(worst, DistanceOutsideHull(p, farthest));
    EXPECT_GT(worst, 0.0003);  // why the hull is simplified by distance, not by a count
  }
}

TEST(CollisionShape, TheFullHullIsKeptWhereTheToleranceNeedsIt) {
  // A 48-sided prism of 2 cm radius sags 0.43 mm between neighbours: none can go.
  const auto exact = ExactHull(test::ManySidedPrism(48, 0.02, 0.01), Eigen::Vector3d::Zero());
  EXPECT_EQ(SimplifiedHull(exact, kTolerance).size(), exact.size());
}

// Hulls of more edge directions than Bullet's separating-axis test is worth take the contact
// normal from the face normals alone. A 96-sided prism (49 edge directions) lies along x with a
// side face on top; a second stands on it, its bottom cap 2 mm below that face: the hulls overlap
// by 2 mm along z (pushing it sideways would take the cap's 12 mm radius), and the contact reads
// it. 1 mm above the face, no contact reads any depth.
TEST(CollisionShape, ManyEdgedHullsInContactReadTheirOverlapAlongTheFaceNormal) {
  PartType prism;
  prism.mesh = test::ManySidedPrism();
  prism.count = 2;
  const std::vector<PartGeometry> geometry = {MakePartGeometry(prism, 0.0)};
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.3, 0.3, 0.3);
  // Body z along world x; turned half a side about its axis so that the side face between the
  // corners at 176.25 and 180 degrees faces up.
  Pose3 lying = Pose3::Identity();
  lying.linear() = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(M_PI / 96, Eigen::Vector3d::UnitZ()))
                       .toRotationMatrix();
  lying.translation() = Eigen::Vector3d(0, 0, 1.0);
  double top = -INFINITY, bottom = INFINITY;
  for (const Eigen::Vector3d& p : geometry[0].hull) top = std::max(top, (lying * p).z()), bottom = std::min(bottom, p.z());
  for (const double gap : {-0.002, 0.001}) {
    auto world = MakeBulletFillWorld(bin, geometry, FillOptions{});
    Pose3 standing = Pose3::Identity();
    standing.translation() = Eigen::Vector3d(0, 0, top + gap - bottom);
    world->AddPart(0, lying);
    world->AddPart(0, standing);
    const ContactDepths depths = world->DeepestContacts();
    EXPECT_NEAR(depths.part_part, std::max(0.0, -gap), 1e-6) << "gap " << gap;
    EXPECT_EQ(depths.part_bin, 0.0);
  }
}

}  // namespace
}  // namespace vscan::physics
