#include "grasp_checks.h"

#include <gtest/gtest.h>

namespace vscan::grasping::testing {

void ExpectSortedRigidGrasps(const std::vector<Grasp>& grasps) {
  for (size_t i = 0; i < grasps.size(); ++i) {
    const Grasp& g = grasps[i];
    EXPECT_GE(g.quality, 0);
    EXPECT_LE(g.quality, 1);
    if (i > 0) {
      EXPECT_LE(g.quality, grasps[i - 1].quality);
    }
    EXPECT_TRUE(g.part_from_tool.linear().isUnitary(1e-9));
    EXPECT_GT(g.part_from_tool.linear().determinant(), 0);
  }
}

}  // namespace vscan::grasping::testing
