#include "reconstruction/mesh_cleanup.h"

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

namespace vscan::reconstruction {
namespace {

TriangleMesh Join(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const auto offset = static_cast<uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return m;
}

TEST(MeshCleanup, SmallComponentsGoLargeOnesStay) {
  const TriangleMesh big = vscan::test::MakeGrid(1.0, 10);  // 200 triangles
  const TriangleMesh small = vscan::test::MakeBox({5, 5, 5}, {6, 6, 6});  // 12 triangles
  TriangleMesh mesh = Join(small, big);
  EXPECT_EQ(RemoveSmallComponents(mesh, 13), 12u);
  EXPECT_EQ(mesh.triangles.size(), big.triangles.size());
  EXPECT_EQ(mesh.vertices.size(), big.vertices.size());
  EXPECT_EQ(mesh.vertices, big.vertices);
  EXPECT_EQ(mesh.triangles, big.triangles);
  EXPECT_EQ(RemoveSmallComponents(mesh, 0), 0u);
}

TEST(MeshCleanup, KeepTrianglesOnVerticesDropsTheRest) {
  TriangleMesh mesh = vscan::test::MakeGrid(1.0, 1);  // 4 vertices, 2 triangles
  std::vector<bool> keep = {true, true, false, true};
  KeepTrianglesOnVertices(mesh, keep);
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.vertices.size(), 3u);
}

}  // namespace
}  // namespace vscan::reconstruction
