#include "physics/mesh_overlap.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "machined_parts.h"
#include "physics/mesh_depth.h"

namespace vscan::physics {
namespace {

// A closed cube [0, side]^3 with outward faces.
TriangleMesh Cube(double side) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(static_cast<float>((i & 1) ? side : 0), static_cast<float>((i & 2) ? side : 0),
                               static_cast<float>((i & 4) ? side : 0));
  }
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

Pose3 At(const Eigen::Vector3d& t, const Eigen::Matrix3d& r = Eigen::Matrix3d::Identity()) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = r;
  pose.translation() = t;
  return pose;
}

TEST(MeshDepth, DepthInsideAndDistanceOutsideACube) {
  const MeshDepth cube(Cube(0.01));
  EXPECT_NEAR(cube.SignedDepth({0.005, 0.005, 0.005}), 0.005, 1e-9);
  EXPECT_NEAR(cube.SignedDepth({0.002, 0.005, 0.009}), 0.001, 1e-9);
  EXPECT_NEAR(cube.Distance({0.013, 0.005, 0.014}), 0.005, 1e-9);
  EXPECT_FALSE(cube.Inside({0.013, 0.005, 0.005}));
  EXPECT_TRUE(cube.Inside({0.0099, 0.0001, 0.005}));
  EXPECT_EQ(cube.edges().size(), 18u);  // 12 sides and 6 face diagonals
}

// Inside a convex mesh the depth is the nearest face's plane distance, which is the distance to the
// nearest triangle only when the planes are the faces' own: planes from Bullet's single-precision
// hull missed the 96-sided prism's faces by up to a micrometre.
TEST(MeshDepth, InsideAManySidedPrismTheDepthIsTheDistanceToItsNearestTriangle) {
  const MeshDepth prism(test::ManySidedPrism());  // radius 12 mm (11.994 mm to a side), 20 mm high
  for (int k = 0; k < 60; ++k) {
    const double angle = 0.1237 * k, radius = 0.0114 + 0.00001 * k;
    const Eigen::Vector3d p(radius * std::cos(angle), radius * std::sin(angle), 0.0005 + 0.0003 * k);
    ASSERT_TRUE(prism.Inside(p)) << k;
    EXPECT_NEAR(prism.SignedDepth(p), prism.Distance(p), 1e-9) << k;
  }
}

// Two 1 cm cubes in a box bin far above its floor, far from its walls.
BinSpec BigBin() {
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.3, 0.3, 0.3);
  return bin;
}

std::vector<PartType> TwoCubes() {
  PartType cube;
  cube.mesh = Cube(0.01);
  cube.count = 2;
  return {cube};
}

TEST(MeshOverlap, FaceToFaceCubesOverlapByTheirShift) {
  const std::vector<PlacedPart> placed = {{0, 0, At({0, 0, 0.1})}, {0, 1, At({0.0097, 0.002, 0.1})}};
  const MeshOverlaps overlap = MeasureMeshOverlaps(BigBin(), TwoCubes(), placed);
  EXPECT_NEAR(overlap.max_part_part_m, 0.0003, kMeshOverlapResolution);
  EXPECT_LE(overlap.max_part_part_m, 0.0003 + 1e-9);
  EXPECT_EQ(overlap.overlapping_pairs, 1u);
  EXPECT_EQ(overlap.p95_part_part_m, overlap.max_part_part_m);
  EXPECT_EQ(overlap.max_part_bin_m, 0.0);
}

TEST(MeshOverlap, ACornerPokingIntoAFaceOverlapsByItsDepth) {
  // The second cube turned so that a corner points along -x, that corner 0.4 mm into the first.
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(std::atan(1 / std::sqrt(2.0)), Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  // The corner farthest along -x after the turn.
  const PartType cube = TwoCubes()[0];
  Eigen::Vector3d lowest = Eigen::Vector3d::Constant(1);
  for (const auto& v : cube.mesh.vertices) {
    const Eigen::Vector3d p = r * v.cast<double>();
    if (p.x() < lowest.x()) lowest = p;
  }
  const Eigen::Vector3d corner_at(0.0096, 0.005, 0.105);
  const std::vector<PlacedPart> placed = {{0, 0, At({0, 0, 0.1})}, {0, 1, At(corner_at - lowest, r)}};
  const MeshOverlaps overlap = MeasureMeshOverlaps(BigBin(), TwoCubes(), placed);
  EXPECT_NEAR(overlap.max_part_part_m, 0.0004, kMeshOverlapResolution + 1e-7);
}

TEST(MeshOverlap, CrossedEdgesOverlapByTheDeepestEdgePoint) {
  // Each cube turned 45 degrees (about y, about z) so that an edge leads; the edges cross 0.5 mm
  // deep. The deepest point of either edge lies 0.5 / sqrt(2) mm from the other cube's faces.
  const double half_diagonal = 0.005 * std::sqrt(2.0);
  const Eigen::Matrix3d about_y = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d about_z = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d centre(0.005, 0.005, 0.005);
  const Eigen::Vector3d a(0, 0, 0.1), b(2 * half_diagonal - 0.0005, 0, 0.1);
  const std::vector<PlacedPart> placed = {{0, 0, At(a - about_y * centre, about_y)},
                                          {0, 1, At(b - about_z * centre, about_z)}};
  const MeshOverlaps overlap = MeasureMeshOverlaps(BigBin(), TwoCubes(), placed);
  const double expected = 0.0005 / std::sqrt(2.0);
  EXPECT_NEAR(overlap.max_part_part_m, expected, kMeshOverlapResolution);
  EXPECT_LE(overlap.max_part_part_m, expected + 1e-9);
}

TEST(MeshOverlap, ApartCubesDoNotOverlapAndACubeSunkInTheFloorOverlapsTheBin) {
  BinSpec bin = BigBin();
  bin.world_from_bin = At({0.3, -0.1, 0.05}, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  const std::vector<PlacedPart> placed = {{0, 0, bin.world_from_bin * At({0, 0, -0.0002})},
                                          {0, 1, bin.world_from_bin * At({0.0101, 0, 0})}};
  const MeshOverlaps overlap = MeasureMeshOverlaps(bin, TwoCubes(), placed);
  EXPECT_EQ(overlap.max_part_part_m, 0.0);
  EXPECT_EQ(overlap.overlapping_pairs, 0u);
  EXPECT_NEAR(overlap.max_part_bin_m, 0.0002, 1e-7);
}

TEST(MeshOverlap, ACubePushedIntoAWallOverlapsTheBin) {
  const BinSpec bin = BigBin();
  const std::vector<PlacedPart> placed = {{0, 0, At({0.15 - 0.0097, 0, 0.05})}};
  std::vector<PartType> one = TwoCubes();
  one[0].count = 1;
  EXPECT_NEAR(MeasureMeshOverlaps(bin, one, placed).max_part_bin_m, 0.0003, 1e-7);
}

// The deepest any point of one axis-aligned cube can lie inside another: along an axis where one
// enters the other from a side, no point of it lies deeper than the overlap of their extents.
double BoundOfCubeOverlap(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double side) {
  double bound = INFINITY;
  for (int k = 0; k < 3; ++k) {
    const double overlap = side - std::abs(a[k] - b[k]);
    if (overlap <= 0) return 0.0;
    if (a[k] != b[k]) bound = std::min(bound, overlap);
  }
  return bound;
}

TEST(MeshSeparation, APartOnTheFloorStaysAndThePartSunkIntoItFromAboveMovesUp) {
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.1, 0.1, 0.1);
  bin.world_from_bin = At({0.3, -0.1, 0.05}, Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix());
  std::vector<PlacedPart> placed = {{0, 0, bin.world_from_bin * At({0, 0, 0})},
                                    {0, 1, bin.world_from_bin * At({0.002, 0.001, 0.009})}};
  const MeshOverlaps overlap = SeparateMeshOverlaps(bin, TwoCubes(), placed, 0.0003, 24);
  const Eigen::Vector3d lower = bin.world_from_bin.inverse() * placed[0].world_from_part.translation();
  const Eigen::Vector3d upper = bin.world_from_bin.inverse() * placed[1].world_from_part.translation();
  // The floor takes none of the push: the lower cube does not sink, the upper one rises.
  EXPECT_GE(lower.z(), -1e-9);
  EXPECT_GE(upper.z() - lower.z(), 0.01 - 0.0003);
  EXPECT_LE(BoundOfCubeOverlap(lower, upper, 0.01), 0.0003 + 1e-7);
  EXPECT_LE(overlap.max_part_part_m, 0.0003);
  EXPECT_LE(overlap.max_part_bin_m, 0.0003);
}

TEST(MeshSeparation, ADenseStackInABinCornerEndsWithinTheBoundWithoutEnteringTheWalls) {
  // 4 x 4 cubes of 1 cm on the floor at 9.2 mm spacing (0.8 mm into each neighbour), the first
  // against two walls, and 3 x 3 more on top sunk 0.8 mm into them.
  BinSpec bin;
  bin.inner_size = Eigen::Vector3d(0.1, 0.1, 0.1);
  const double side = 0.01, pitch = 0.0092;
  std::vector<PlacedPart> placed;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) placed.push_back({0, placed.size(), At({-0.05 + i * pitch, -0.05 + j * pitch, 0})});
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      placed.push_back({0, placed.size(), At({-0.05 + (i + 0.5) * pitch, -0.05 + (j + 0.5) * pitch, side - 0.0008})});
    }
  }
  std::vector<PartType> cubes = TwoCubes();
  cubes[0].count = placed.size();
  const double bound = 0.0003;
  const MeshOverlaps overlap = SeparateMeshOverlaps(bin, cubes, placed, bound, 24);
  EXPECT_LE(overlap.max_part_part_m, bound);
  EXPECT_LE(overlap.max_part_bin_m, bound);
  EXPECT_GT(overlap.moved_parts, 0u);
  for (size_t a = 0; a < placed.size(); ++a) {
    const Eigen::Vector3d p = placed[a].world_from_part.translation();
    EXPECT_GE(p.z(), -bound) << a;
    EXPECT_GE(p.x(), -0.05 - bound) << a;
    EXPECT_GE(p.y(), -0.05 - bound) << a;
    for (size_t b = a + 1; b < placed.size(); ++b) {
      EXPECT_LE(BoundOfCubeOverlap(p, placed[b].world_from_part.translation(), side), bound + kMeshOverlapResolution)
          << a << " " << b;
    }
  }
}

}  // namespace
}  // namespace vscan::physics
