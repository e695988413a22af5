#include <gtest/gtest.h>

#include <cmath>

#include "fixture_parts.h"
#include "hull_support.h"
#include "machined_parts.h"
#include "physics/bin_fill.h"
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

}  // namespace
}  // namespace vscan::physics
