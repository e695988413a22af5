#include "localization/part_model_cache.h"

#include <gtest/gtest.h>

#include "vscan_test/meshes.h"

namespace vscan::localization {
namespace {

StatusOr<PartModel> BuildBox(double side, int* builds) {
  ++*builds;
  return BuildPartModel(test::MakeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(side)), "part", {});
}

TEST(PartModelCache, KeepsTheMostRecentlyUsedModels) {
  PartModelCache cache(2);
  int builds = 0;
  auto first = cache.Get("a", [&] { return BuildBox(0.02, &builds); });
  ASSERT_TRUE(first.ok()) << first.status().ToString();
  auto again = cache.Get("a", [&] { return BuildBox(0.02, &builds); });
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(first->get(), again->get());
  EXPECT_EQ(builds, 1);
  ASSERT_TRUE(cache.Get("b", [&] { return BuildBox(0.03, &builds); }).ok());
  ASSERT_TRUE(cache.Get("a", [&] { return BuildBox(0.02, &builds); }).ok());  // a is the most recent now
  ASSERT_TRUE(cache.Get("c", [&] { return BuildBox(0.04, &builds); }).ok());  // b leaves
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_EQ(builds, 3);
  ASSERT_TRUE(cache.Get("a", [&] { return BuildBox(0.02, &builds); }).ok());
  EXPECT_EQ(builds, 3);
  ASSERT_TRUE(cache.Get("b", [&] { return BuildBox(0.03, &builds); }).ok());
  EXPECT_EQ(builds, 4);
}

TEST(PartModelCache, BoundsTheBytesKeptAndKeepsNoFailure) {
  int builds = 0;
  auto one = BuildBox(0.02, &builds);
  ASSERT_TRUE(one.ok());
  EXPECT_GT(one->MemoryBytes(), one->ppf->pair_count() * 8);
  PartModelCache cache(8, one->MemoryBytes() + one->MemoryBytes() / 2);
  ASSERT_TRUE(cache.Get("a", [&] { return BuildBox(0.02, &builds); }).ok());
  ASSERT_TRUE(cache.Get("b", [&] { return BuildBox(0.02, &builds); }).ok());
  EXPECT_EQ(cache.size(), 1u);  // two would pass the bytes allowed
  EXPECT_LE(cache.bytes(), one->MemoryBytes() + one->MemoryBytes() / 2);
  const auto failed = cache.Get("empty", [] { return BuildPartModel(TriangleMesh{}, "parts[0]", {}); });
  EXPECT_EQ(failed.status().field(), "parts[0]");
  EXPECT_EQ(cache.size(), 1u);
}

TEST(PartModelCache, KeysNameTheMeshScaleAndSettings) {
  PartModelSettings settings;
  const std::string key = PartModelKey("msh_1", 1.0, settings);
  EXPECT_NE(key, PartModelKey("msh_2", 1.0, settings));
  EXPECT_NE(key, PartModelKey("msh_1", 0.5, settings));
  settings.voxel_size = 0.002;
  EXPECT_NE(key, PartModelKey("msh_1", 1.0, settings));
}

}  // namespace
}  // namespace vscan::localization
