#include "physics/convex_decomposition.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fixture_parts.h"
#include "hull_support.h"
#include "machined_parts.h"
#include "physics/bin_fill.h"
#include "physics/decomposition_store.h"
#include "physics/mesh_depth.h"
#include "physics/part_geometry.h"
#include "physics/plane_cut_decomposition.h"

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

TEST(ConvexDecomposition, AMeshTooLargeForItIsRefusedBeforeAnyWork) {
  PartType part;
  part.name = "torus";
  part.mesh = test::Torus(150);  // 22500 triangles
  part.count = 2;
  part.collision = PartCollision::kConvexDecomposition;
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.3, 0.3, 0.2);
  const auto refused = FillBin(bin, {part}, FillOptions{});
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(refused.status().field(), "parts[0].mesh");
  EXPECT_NE(refused.status().ToString().find("this one has 22500"), std::string::npos) << refused.status().ToString();
  // The convex hull of the same mesh is no trouble.
  part.collision = PartCollision::kConvexHull;
  FillOptions quick;
  quick.measure_mesh_overlaps = false;  // 22500-triangle meshes: seconds, and not the point here
  quick.hull_tolerance_m = 0.002;
  EXPECT_TRUE(FillBin(bin, {part}, quick).ok());
}

// A prism of `outline` (counter-clockwise, metres) from z = 0 to `height`; `caps` triangulate the
// outline (counter-clockwise seen from above), the bottom cap facing down.
TriangleMesh Extruded(const std::vector<Eigen::Vector2d>& outline, const std::vector<std::array<uint32_t, 3>>& caps,
                      double height) {
  TriangleMesh mesh;
  const auto n = static_cast<uint32_t>(outline.size());
  for (double z : {0.0, height}) {
    for (const auto& p : outline) mesh.vertices.emplace_back(float(p.x()), float(p.y()), float(z));
  }
  for (const auto& t : caps) {
    mesh.triangles.push_back({t[0], t[2], t[1]});
    mesh.triangles.push_back({n + t[0], n + t[1], n + t[2]});
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({i, j, n + j});
    mesh.triangles.push_back({i, n + j, n + i});
  }
  return mesh;
}

// A U of 3 x 3 cm, arms 1 cm wide, 1 cm thick: its slot is the square x in (1, 2), y in (1, 3) cm.
TriangleMesh UPrism() {
  std::vector<Eigen::Vector2d> outline;
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}) {
    outline.emplace_back(0.01 * x, 0.01 * y);
  }
  return Extruded(outline, {{0, 1, 4}, {0, 4, 5}, {1, 2, 3}, {1, 3, 4}, {0, 5, 6}, {0, 6, 7}}, 0.01);
}

// A 3 x 3 cm square, 1 cm thick, with a notch `notch` metres square cut from one corner.
TriangleMesh NotchedSquare(double notch) {
  const double s = 0.03;
  return Extruded({{0, 0}, {s, 0}, {s, s - notch}, {s - notch, s - notch}, {s - notch, s}, {0, s}},
                  {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}}, 0.01);
}

// A closed tube along z: `sides` sides, radii outer and inner, `length` long.
TriangleMesh Tube(int sides, double outer, double inner, double length) {
  TriangleMesh mesh;
  const auto n = static_cast<uint32_t>(sides);
  for (double r : {outer, inner}) {
    for (double z : {0.0, length}) {
      for (uint32_t i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        mesh.vertices.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), float(z));
      }
    }
  }
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t j = (i + 1) % n;
    mesh.triangles.push_back({i, j, n + j});  // outside
    mesh.triangles.push_back({i, n + j, n + i});
    mesh.triangles.push_back({2 * n + i, 3 * n + j, 2 * n + j});  // the bore, facing the axis
    mesh.triangles.push_back({2 * n + i, 3 * n + i, 3 * n + j});
    mesh.triangles.push_back({n + i, n + j, 3 * n + j});  // top ring
    mesh.triangles.push_back({n + i, 3 * n + j, 3 * n + i});
    mesh.triangles.push_back({i, 2 * n + j, j});  // bottom ring
    mesh.triangles.push_back({i, 2 * n + i, 2 * n + j});
  }
  return mesh;
}

bool Convex(const TriangleMesh& mesh, double tolerance) {
  const Eigen::Vector3d centre(0.01, 0.01, 0.005);
  return ConvexWithin(mesh, centre, ExactHull(mesh, centre), tolerance);
}

TEST(ConvexDecomposition, ConvexWithinAToleranceIsDecidedByTheDeepestPointUnderTheHullAndTheHollowsVolume) {
  EXPECT_TRUE(Convex(test::ManySidedPrism(), 0.00001));
  EXPECT_TRUE(Convex(NotchedSquare(0), 0.00001));
  // A 0.2 mm notch: its corner lies 0.2 / sqrt(2) = 0.14 mm under the hull's bevel.
  EXPECT_TRUE(Convex(NotchedSquare(0.0002), 0.00015));
  EXPECT_FALSE(Convex(NotchedSquare(0.0002), 0.00013));
  EXPECT_FALSE(Convex(LPrism(), 0.0002));
  EXPECT_FALSE(Convex(UPrism(), 0.0002));
  // A tube with a 0.4 mm wall (the fixture pin's): its bore's surface lies 0.4 mm under the
  // hull's, but the hull holds the whole bore, far more than a 0.5 mm shell under its faces.
  EXPECT_FALSE(Convex(Tube(32, 0.0033, 0.0029, 0.079), 0.0005));
}

TEST(ConvexDecomposition, AConvexPartIsItsHullUncutAndAUKeepsItsSlotOpen) {
  const TriangleMesh prism = test::ManySidedPrism();
  const Eigen::Vector3d centre(0, 0, 0.01);
  const auto pieces = ConvexPieces(prism, centre, 0.0002);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0], SimplifiedHull(ExactHull(prism, centre), 0.0002));

  const TriangleMesh u = UPrism();
  const Eigen::Vector3d middle(0.015, 0.015, 0.005);
  const auto u_pieces = ConvexPieces(u, middle, 0.0002);
  ASSERT_GE(u_pieces.size(), 2u);
  // The middle of the slot lies inside the U's hull but more than 2 mm outside every piece.
  const Eigen::Vector3d slot = Eigen::Vector3d(0.015, 0.02, 0.005) - middle;
  EXPECT_EQ(OutsideBy(slot, ExactHull(u, middle)), 0.0);
  for (const auto& piece : u_pieces) EXPECT_GT(OutsideBy(slot, piece), 0.002);
}

TEST(PlaneCuts, ATubesBoreAndATorussHoleStayOpen) {
  // No single plane opens a bore (each half's hull still spans it): the tube is cut in quarters.
  const TriangleMesh tube = Tube(32, 0.0033, 0.0029, 0.079);
  const Eigen::Vector3d tube_centre(0, 0, 0.0395);
  PlaneCutOptions options;
  options.concavity_m = 0.0015;
  const auto tube_pieces = PlaneCutPieces(tube, tube_centre, options);
  ASSERT_GE(tube_pieces.size(), 4u);
  // The axis lies 2.9 mm from the wall and a hull within 1.5 mm of the solid, so at least 1.4 mm
  // from any piece (less the samples' spacing).
  for (const double z : {0.01, 0.04, 0.07}) {
    for (const auto& piece : tube_pieces) EXPECT_GT(OutsideBy(Eigen::Vector3d(0, 0, z) - tube_centre, piece), 0.0012);
  }
  // ConvexPieces' bound for a 79 mm part (5%, 4 mm) keeps a 2.9 mm bore closed: one hull.
  EXPECT_EQ(ConvexPieces(tube, tube_centre, 0.0002).size(), 1u);
  const TriangleMesh torus = test::Torus(40);
  const auto torus_pieces = ConvexPieces(torus, Eigen::Vector3d::Zero(), 0.0002);
  ASSERT_GE(torus_pieces.size(), 4u);
  // The hole's middle, 3 cm inside the ring's inner edge, lies outside every piece.
  for (const auto& piece : torus_pieces) EXPECT_GT(OutsideBy(Eigen::Vector3d::Zero(), piece), 0.01);
}

TEST(PlaneCuts, PiecesReachNoFartherFromTheSolidThanTheBoundOrTheHull) {
  PlaneCutOptions options;
  options.concavity_m = 0.0006;
  const std::vector<std::pair<std::string, TriangleMesh>> meshes = {
      {"L", LPrism()}, {"U", UPrism()}, {"angle block", test::AngleBlock(1).mesh}};
  for (const auto& [name, part_mesh] : meshes) {
    SCOPED_TRACE(name);
    const TriangleMesh* mesh = &part_mesh;
    const bool block = name == "angle block";
    Eigen::Vector3f lo, hi;
    mesh->Bounds(lo, hi);
    const Eigen::Vector3d centre = (0.5f * (lo + hi)).cast<double>();
    const auto pieces = PlaneCutPieces(*mesh, centre, options);
    ASSERT_FALSE(pieces.empty());
    const double hull_reach = HullReach(*mesh, centre, ExactHull(*mesh, centre), 0.0002);
    EXPECT_GT(hull_reach, options.concavity_m);
    // Measured on a grid finer than the cut's own samples. The L and the U are cut to the bound;
    // the angle block's bore needs more than max_pieces, and its pieces must still reach less far.
    double worst = 0.0;
    for (const auto& piece : pieces) worst = std::max(worst, HullReach(*mesh, centre, piece, 0.0002));
    if (block) {
      EXPECT_EQ(pieces.size(), options.max_pieces);
      EXPECT_LT(worst, 0.75 * hull_reach);
    } else {
      EXPECT_LE(worst, options.concavity_m + 0.0002);
    }
    // Together the pieces hold the solid: every vertex lies inside one of them.
    for (const Eigen::Vector3f& v : mesh->vertices) {
      double nearest = INFINITY;
      for (const auto& piece : pieces) nearest = std::min(nearest, OutsideBy(v.cast<double>() - centre, piece));
      EXPECT_LT(nearest, 1e-5);
    }
  }
}

TEST(MeshDepthOfAnL, ItsNotchIsOutsideThoughTheNotchCornerLiesOnTheHullsTopFace) {
  // A mesh is taken for convex (depths by plane distances) only when no point lies under its hull.
  const MeshDepth depth(LPrism());
  EXPECT_FALSE(depth.Inside(Eigen::Vector3d(0.02, 0.02, 0.005)));
  EXPECT_NEAR(depth.SignedDepth(Eigen::Vector3d(0.02, 0.02, 0.005)), -0.01, 1e-9);
  EXPECT_NEAR(depth.SignedDepth(Eigen::Vector3d(0.005, 0.005, 0.004)), 0.004, 1e-9);
  // Beyond a hull plane: minus that plane's distance, no farther than the surface.
  EXPECT_NEAR(depth.SignedDepth(Eigen::Vector3d(0.035, 0.005, 0.005)), -0.005, 1e-9);
  // A box is its hull: inside, the depth is the nearest face's distance.
  const MeshDepth box(test::ManySidedPrism(4, 0.01, 0.01));
  EXPECT_TRUE(box.Inside(Eigen::Vector3d(0.001, 0.0, 0.002)));
  EXPECT_NEAR(box.SignedDepth(Eigen::Vector3d(0.001, 0.0, 0.002)), 0.002, 1e-6);
}

TEST(PlaneCuts, TheFixtureAngleBlocksPiecesHoldItsMeshWithinTheHullTolerance) {
  const PartType block = test::AngleBlock(1);
  const PartGeometry geometry = MakePartGeometries({[&] {
    PartType part = block;
    part.collision = PartCollision::kConvexDecomposition;
    return part;
  }()}, 0.0002)[0];
  ASSERT_GE(geometry.pieces.size(), 2u);
  double worst = 0.0;
  for (const Eigen::Vector3f& v : block.mesh.vertices) {
    double nearest = INFINITY;
    for (const auto& piece : geometry.pieces) nearest = std::min(nearest, OutsideBy(v.cast<double>() - geometry.centre, piece));
    worst = std::max(worst, nearest);
  }
  EXPECT_LE(worst, 0.0002 + 1e-5);
}

std::string FreshDirectory(const char* name) {
  const auto dir = std::filesystem::temp_directory_path() / (std::string(name) + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  return dir.string();
}

TEST(DecompositionStore, PiecesComeBackOnlyForTheKeyTheyWereStoredUnder) {
  const std::string dir = FreshDirectory("vscan_store_test");
  const PiecesKey key{0x1234, 0x5678, 8, 12};
  const ConvexPieceSet pieces = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{2, 2, 2}, {3, 2, 2}, {2, 3, 2}, {2, 2, 3.5}}};
  EXPECT_FALSE(LoadPieces(dir, key).has_value());
  ASSERT_TRUE(StorePieces(dir, key, pieces));
  const auto loaded = LoadPieces(dir, key);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(*loaded, pieces);
  PiecesKey other_check = key, other_size = key;
  other_check.check = 0x5679;
  other_size.triangles = 13;
  EXPECT_FALSE(LoadPieces(dir, other_check).has_value());
  EXPECT_FALSE(LoadPieces(dir, other_size).has_value());
  // A file cut short is not read.
  const auto file = std::filesystem::directory_iterator(dir)->path();
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 4);
  EXPECT_FALSE(LoadPieces(dir, key).has_value());
  std::filesystem::remove_all(dir);
}

TEST(DecompositionStore, ConvexPiecesReadsTheDirectoryBeforeCuttingAndFillsIt) {
  const std::string dir = FreshDirectory("vscan_pieces_test");
  SetDecompositionDirectory(dir);
  const TriangleMesh l = LPrism();
  const Eigen::Vector3d centre(0.01, 0.01, 0.005);
  // Tolerances no other test uses, so that the process's own cache has neither.
  const double computed_at = 0.000061, planted_at = 0.000062;
  const auto computed = ConvexPieces(l, centre, computed_at);
  ASSERT_GE(computed.size(), 2u);
  const auto stored = LoadPieces(dir, DecompositionKey(l, centre, computed_at));
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(*stored, computed);
  // Pieces planted under the key are what ConvexPieces returns: no cut ran.
  const ConvexPieceSet planted = {{{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 0.01}}};
  ASSERT_TRUE(StorePieces(dir, DecompositionKey(l, centre, planted_at), planted));
  EXPECT_EQ(ConvexPieces(l, centre, planted_at), planted);
  SetDecompositionDirectory("");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vscan::physics
