#include "reconstruction/cube_cases.h"

#include <set>

#include <gtest/gtest.h>

namespace vscan::reconstruction {
namespace {

TEST(CubeCases, EmptyAndFullCubesHaveNoTriangles) {
  EXPECT_TRUE(CubeCase(0).empty());
  EXPECT_TRUE(CubeCase(255).empty());
}

TEST(CubeCases, EdgesRunAlongTheirAxisFromTheirStart) {
  std::set<std::pair<int, int>> seen;
  for (int e = 0; e < 12; ++e) {
    const int start = EdgeStart(e);
    EXPECT_EQ(start & (1 << EdgeAxis(e)), 0) << e;
    seen.insert({start, EdgeAxis(e)});
  }
  EXPECT_EQ(seen.size(), 12u);
}

// Each case puts vertices on exactly the edges whose two corners differ.
TEST(CubeCases, EveryCaseCutsExactlyItsSignChanges) {
  for (uint32_t mask = 1; mask < 255; ++mask) {
    std::set<int> cut, used;
    for (int e = 0; e < 12; ++e) {
      const int c0 = EdgeStart(e), c1 = c0 | (1 << EdgeAxis(e));
      if (((mask >> c0) & 1) != ((mask >> c1) & 1)) cut.insert(e);
    }
    for (const CubeTriangle& t : CubeCase(mask)) {
      EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) << mask;
      used.insert(t.begin(), t.end());
    }
    EXPECT_EQ(used, cut) << "case " << mask;
  }
}

}  // namespace
}  // namespace vscan::reconstruction
