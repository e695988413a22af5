#include "geometry/mesh_import.h"

#include <gtest/gtest.h>

#include <set>

#include "mesh_test_util.h"

namespace vscan::geometry {
namespace {

using test::Expected;
using test::Point;

std::set<Point> VertexSet(const TriangleMesh& mesh) {
  std::set<Point> points;
  for (const auto& v : mesh.vertices) points.insert({v.x(), v.y(), v.z()});
  return points;
}

void ExpectMatches(const TriangleMesh& mesh, const Expected& expected) {
  EXPECT_EQ(mesh.triangles.size(), expected.triangles);
  EXPECT_EQ(mesh.vertices.size(), expected.vertices.size());
  EXPECT_TRUE(VertexSet(mesh) == expected.vertices);
  Eigen::Vector3f min, max;
  mesh.Bounds(min, max);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(min[k], expected.min[k]) << "axis " << k;
    EXPECT_EQ(max[k], expected.max[k]) << "axis " << k;
  }
}

void ExpectWellFormed(const TriangleMesh& mesh) {
  std::set<std::array<uint32_t, 3>> seen;
  for (const auto& t : mesh.triangles) {
    for (uint32_t i : t) ASSERT_LT(i, mesh.vertices.size());
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
  }
  EXPECT_EQ(VertexSet(mesh).size(), mesh.vertices.size()) << "duplicate vertices survived the merge";
}

TEST(MeshImportTest, BunnyPlyKeepsEveryTriangle) {
  std::string bytes = test::ReadDataFile("meshes/bunny/bunny_zipper_res2.ply");
  ASSERT_FALSE(bytes.empty());
  auto mesh = ImportMesh(bytes, MeshFileFormat::kPly, 1.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  // No face of this file is degenerate, so all 16301 stay (assimp's default area test would drop 257);
  // 25 of the 8171 vertices are used by no face and go.
  EXPECT_EQ(mesh->triangles.size(), 16301u);
  EXPECT_EQ(mesh->vertices.size(), 8146u);

  Expected expected = test::ExpectFromSoup(test::ParseAsciiPly(bytes), 1.0);
  ASSERT_EQ(expected.triangles, 16301u);
  Eigen::Vector3f min, max;
  mesh->Bounds(min, max);
  for (int k = 0; k < 3; ++k) {
    // Different decimal parsers may round the last bit differently.
    EXPECT_NEAR(min[k], expected.min[k], 1e-7);
    EXPECT_NEAR(max[k], expected.max[k], 1e-7);
  }
  EXPECT_NEAR(max.y() - min.y(), 0.153, 0.005);
}

TEST(MeshImportTest, SpotObj) {
  std::string bytes = test::ReadDataFile("meshes/spot/spot.obj");
  ASSERT_FALSE(bytes.empty());
  auto mesh = ImportMesh(bytes, MeshFileFormat::kObj, 1.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  EXPECT_EQ(mesh->triangles.size(), 5856u);
  // Texture seams split vertices inside assimp; merging by position brings them back together.
  EXPECT_EQ(mesh->vertices.size(), 2930u);
}

struct StlCase {
  const char* file;
  double metres_per_unit;
  std::array<double, 3> extent_units;  // as drawn, in the file's own unit
};

class StlImportTest : public ::testing::TestWithParam<StlCase> {};

TEST_P(StlImportTest, ExtentsMatchAnIndependentReading) {
  const StlCase& c = GetParam();
  std::string bytes = test::ReadDataFile(std::string("parts/") + c.file);
  ASSERT_GT(bytes.size(), 84u);
  Expected expected = test::ExpectFromSoup(test::ParseBinaryStl(bytes), c.metres_per_unit);
  auto mesh = ImportMesh(bytes, MeshFileFormat::kStl, c.metres_per_unit);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  ExpectMatches(*mesh, expected);

  Eigen::Vector3f min, max;
  mesh->Bounds(min, max);
  Eigen::Vector3f extent = max - min;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(extent[k], c.extent_units[k] * c.metres_per_unit, 1e-6) << "axis " << k;

  // Sniffing must find STL even though some of these binary files start with "solid".
  auto sniffed = ImportMesh(bytes, MeshFileFormat::kAuto, c.metres_per_unit);
  ASSERT_TRUE(sniffed.ok()) << sniffed.status().ToString();
  EXPECT_EQ(sniffed->triangles.size(), mesh->triangles.size());
}

INSTANTIATE_TEST_SUITE_P(Parts, StlImportTest,
                         ::testing::Values(StlCase{"angle_block.STL", 0.0254, {1.33858, 1.0, 1.35198}},
                                           StlCase{"round.stl", 0.0254, {5.08, 5.08, 60.96}},
                                           StlCase{"plate_holes.STL", 0.001, {203.2, 304.8, 12.7}}));

constexpr char kCubePly[] =
    "ply\n"
    "format ascii 1.0\n"
    "comment a 10 x 20 x 30 box\n"
    "element vertex 8\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 6\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n10 0 0\n10 20 0\n0 20 0\n0 0 30\n10 0 30\n10 20 30\n0 20 30\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TEST(MeshImportTest, CubeInMillimetresHasExactCorners) {
  auto mesh = ImportMesh(kCubePly, MeshFileFormat::kAuto, 0.001);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  EXPECT_EQ(mesh->triangles.size(), 12u);
  std::set<Point> expected;
  for (double x : {0.0, 10.0}) {
    for (double y : {0.0, 20.0}) {
      for (double z : {0.0, 30.0}) {
        expected.insert({static_cast<float>(x * 0.001), static_cast<float>(y * 0.001), static_cast<float>(z * 0.001)});
      }
    }
  }
  EXPECT_TRUE(VertexSet(*mesh) == expected);
  EXPECT_EQ(mesh->vertices.size(), 8u);
}

TEST(MeshImportTest, ObjPolygonsAreTriangulatedAndSharedCornersMerged) {
  // Two objects share an edge; a third triangle repeats a position and is dropped.
  constexpr char kObj[] =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 0\nv 2 0 0\n"
      "o first\nf 1 2 3 4\n"
      "o second\nf 2 6 3\n"
      "o degenerate\nf 1 5 2\n";
  auto mesh = ImportMesh(kObj, MeshFileFormat::kObj, 2.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  EXPECT_EQ(mesh->triangles.size(), 3u);
  EXPECT_EQ(mesh->vertices.size(), 5u);
  Eigen::Vector3f min, max;
  mesh->Bounds(min, max);
  EXPECT_EQ(max, Eigen::Vector3f(4, 2, 0));
}

TEST(MeshImportTest, NegativeZeroMergesWithZero) {
  constexpr char kObj[] =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -0 -0 -0\nv 0 -1 0\n"
      "o a\nf 1 2 3\n"
      "o b\nf 4 5 2\n";
  auto mesh = ImportMesh(kObj, MeshFileFormat::kObj, 1.0);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  ExpectWellFormed(*mesh);
  EXPECT_EQ(mesh->triangles.size(), 2u);
  EXPECT_EQ(mesh->vertices.size(), 4u);
}

TEST(MeshImportTest, TriangleLimitIsResourceExhausted) {
  auto mesh = ImportMesh(kCubePly, MeshFileFormat::kPly, 1.0, 11);
  ASSERT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), StatusCode::kResourceExhausted) << mesh.status().ToString();
  EXPECT_TRUE(ImportMesh(kCubePly, MeshFileFormat::kPly, 1.0, 12).ok());
}

}  // namespace
}  // namespace vscan::geometry
