#include "evaluation/surface_sampling.h"

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

namespace vscan::evaluation {
namespace {

TEST(SurfaceSampling, AreaOfASquareAndABox) {
  EXPECT_NEAR(SurfaceArea(test::MakeGrid(1.0, 5)), 4.0, 1e-9);
  EXPECT_NEAR(SurfaceArea(test::MakeBox({0, 0, 0}, {1, 2, 3})), 2 * (2 + 3 + 6), 1e-9);
}

TEST(SurfaceSampling, UniformByAreaAndSeeded) {
  // A box whose faces differ in area: each face gets samples in proportion to its area.
  const TriangleMesh box = test::MakeBox({0, 0, 0}, {1, 2, 3});
  const auto samples = SampleSurface(box, 220'000, 7);
  ASSERT_EQ(samples.size(), 220'000u);
  size_t on_z_faces = 0;  // the two 1 x 2 faces: 4 / 22 of the area
  for (const auto& p : samples) {
    ASSERT_TRUE(p.x() >= -1e-6f && p.x() <= 1 + 1e-6f && p.y() >= -1e-6f && p.y() <= 2 + 1e-6f);
    if (std::abs(p.z()) < 1e-6f || std::abs(p.z() - 3) < 1e-6f) ++on_z_faces;
  }
  EXPECT_NEAR(static_cast<double>(on_z_faces) / samples.size(), 4.0 / 22.0, 0.005);
  EXPECT_EQ(SampleSurface(box, 1000, 7), SampleSurface(box, 1000, 7));
  EXPECT_NE(SampleSurface(box, 1000, 7), SampleSurface(box, 1000, 8));
}

TEST(SurfaceSampling, EmptyMeshGivesNoSamples) { EXPECT_TRUE(SampleSurface(TriangleMesh{}, 10, 1).empty()); }

}  // namespace
}  // namespace vscan::evaluation
