#include "physics/convex_decomposition.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "hull_support.h"
#include "physics/bin_fill.h"
#include "physics/part_geometry.h"

namespace vscan::physics {
namespace {

// An L-shaped prism: arms 3 cm long and 1 cm wide in x and y, 1 cm thick, its notch the square
// x, y in (1, 3) cm.
TriangleMesh LPrism() {
  const std::array<Eigen::Vector2f, 6> outline = {Eigen::Vector2f(0, 0), Eigen::Vector2f(3, 0), Eigen::Vector2f(3, 1),
                                                  Eigen::Vector2f(1, 1), Eigen::Vector2f(1, 3), Eigen::Vector2f(0, 3)};
  TriangleMesh mesh;
  for (float z : {0.0f, 1.0f}) {
    for (const auto& p : outline) mesh.vertices.emplace_back(0.01f * p.x(), 0.01f * p.y(), 0.01f * z);
  }
  // Caps as a fan about the first corner (every triangle lies inside the L), the top one facing up.
  for (uint32_t i = 1; i + 1 < 6; ++i) {
    mesh.triangles.push_back({0, i + 1, i});
    mesh.triangles.push_back({6, 6 + i, 6 + i + 1});
  }
  for (uint32_t i = 0; i < 6; ++i) {
    const uint32_t j = (i + 1) % 6;
    mesh.triangles.push_back({i, j, 6 + j});
    mesh.triangles.push_back({i, 6 + j, 6 + i});
  }
  return mesh;
}

double OutsideBy(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& points) {
  return test::OutsideHullBy(p, points, 4000);
}

TEST(ConvexDecomposition, AnLShapeSplitsIntoPiecesThatLeaveItsNotchOpen) {
  const TriangleMesh mesh = LPrism();
  const Eigen::Vector3d centre(0.01, 0.01, 0.005);
  const auto pieces = ConvexPieces(mesh, centre, 0.00005);
  ASSERT_GE(pieces.size(), 2u);
  const auto hull = ExactHull(mesh, centre);
  // The middle of the notch is inside the hull but more than 2 mm outside every piece.
  const Eigen::Vector3d notch = Eigen::Vector3d(0.02, 0.02, 0.005) - centre;
  EXPECT_EQ(OutsideBy(notch, hull), 0.0);
  for (const auto& piece : pieces) EXPECT_GT(OutsideBy(notch, piece), 0.002);
  // Points of the solid, both arms and the corner, are each inside some piece.
  for (const Eigen::Vector3d& solid : {Eigen::Vector3d(0.005, 0.005, 0.005), Eigen::Vector3d(0.025, 0.005, 0.005),
                                       Eigen::Vector3d(0.005, 0.025, 0.005)}) {
    double nearest = INFINITY;
    for (const auto& piece : pieces) nearest = std::min(nearest, OutsideBy(solid - centre, piece));
    EXPECT_LT(nearest, 1e-4) << solid.transpose();
  }
}

TEST(ConvexDecomposition, PartsOfOneMeshShareTheirPieces) {
  PartType part;
  part.mesh = LPrism();
  part.count = 1;
  part.collision = PartCollision::kConvexDecomposition;
  PartType hull_part = part;
  hull_part.collision = PartCollision::kConvexHull;
  const auto geometry = MakePartGeometries({part, hull_part, part}, 0.00005);
  ASSERT_EQ(geometry.size(), 3u);
  EXPECT_GE(geometry[0].pieces.size(), 2u);
  EXPECT_TRUE(geometry[1].pieces.empty());
  ASSERT_EQ(geometry[2].pieces.size(), geometry[0].pieces.size());
  for (size_t i = 0; i < geometry[0].pieces.size(); ++i) EXPECT_EQ(geometry[2].pieces[i], geometry[0].pieces[i]);
}

TEST(ConvexDecomposition, LShapedPartsFillABinAndSettleInsideIt) {
  PartType part;
  part.name = "l_prism";
  part.mesh = LPrism();
  part.count = 12;
  part.collision = PartCollision::kConvexDecomposition;
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.12, 0.10, 0.08);
  auto result = FillBin(bin, {part}, FillOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->end, FillEnd::kSettled) << result->message;
  EXPECT_EQ(result->parts.size(), 12u);
  EXPECT_LT(result->max_part_part_penetration_m, 0.002);
  EXPECT_LT(result->max_part_bin_penetration_m, 0.002);
  for (const PlacedPart& placed : result->parts) {
    for (const Eigen::Vector3f& v : part.mesh.vertices) {
      const Eigen::Vector3d p = placed.world_from_part * v.cast<double>();
      EXPECT_LE(std::abs(p.x()), 0.5 * bin.inner_size.x() + 0.002);
      EXPECT_LE(std::abs(p.y()), 0.5 * bin.inner_size.y() + 0.002);
      EXPECT_GE(p.z(), -0.002);
    }
  }
}

// A torus of n x n/2 quads: not convex, so decomposition would run HACD on all of them.
TriangleMesh Torus(int n) {
  const int m = n / 2;
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m, r = 0.05 + 0.02 * std::cos(v);
      mesh.vertices.emplace_back(float(r * std::cos(u)), float(r * std::sin(u)), float(0.02 * std::sin(v)));
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const auto at = [&](int a, int b) { return uint32_t((a % n) * m + b % m); };
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

TEST(ConvexDecomposition, AMeshTooLargeForItIsRefusedBeforeAnyWork) {
  PartType part;
  part.name = "torus";
  part.mesh = Torus(70);  // 4900 triangles: over a minute of HACD
  part.count = 2;
  part.collision = PartCollision::kConvexDecomposition;
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.3, 0.3, 0.2);
  const auto refused = FillBin(bin, {part}, FillOptions{});
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.status().field(), "parts[0].mesh");
  EXPECT_NE(refused.status().ToString().find("this one has 4900"), std::string::npos) << refused.status().ToString();
  // The convex hull of the same mesh is no trouble.
  part.collision = PartCollision::kConvexHull;
  EXPECT_TRUE(FillBin(bin, {part}, FillOptions{}).ok());
}

}  // namespace
}  // namespace vscan::physics
