#include <gtest/gtest.h>

#include "render_test_scenes.h"
#include "vscan/render/cloud_colours.h"
#include "vscan/render/colour_map.h"

namespace vscan::render {
namespace {

TEST(TurboTest, RunsFromDarkBlueThroughGreenToRed) {
  const Eigen::Vector3f low = Turbo(0), mid = Turbo(0.5f), high = Turbo(1);
  EXPECT_LT(low.sum(), 0.5f);
  EXPECT_GT(low.z(), low.y());
  EXPECT_GT(mid.y(), mid.x());
  EXPECT_GT(mid.y(), mid.z());
  EXPECT_GT(high.x(), 0.4f);
  EXPECT_LT(high.y() + high.z(), 0.1f);
  // Clamped outside [0, 1].
  EXPECT_EQ(Turbo(-3), low);
  EXPECT_EQ(Turbo(7), high);
}

TEST(TurboTest, InverseLookUpRecoversTheParameter) {
  for (float t = 0; t <= 1.0f; t += 0.05f) {
    const Eigen::Vector3f c = Turbo(t) * 255.0f;
    const std::array<uint8_t, 3> rgb = {static_cast<uint8_t>(c.x() + 0.5f), static_cast<uint8_t>(c.y() + 0.5f),
                                        static_cast<uint8_t>(c.z() + 0.5f)};
    EXPECT_NEAR(test::InverseTurbo(rgb), t, 0.02f) << "t = " << t;
  }
}

TEST(InstanceColourTest, ZeroIsGreyAndOtherIdsAreDistinct) {
  EXPECT_EQ(InstanceColour(0), Eigen::Vector3f::Constant(kInstanceZeroGrey));
  constexpr uint32_t kIds = 24;
  for (uint32_t a = 1; a <= kIds; ++a) {
    const Eigen::Vector3f ca = InstanceColour(a);
    EXPECT_GT(ca.maxCoeff() - ca.minCoeff(), 0.3f) << "id " << a << " is too grey";
    for (uint32_t b = a + 1; b <= kIds; ++b) {
      EXPECT_GT((ca - InstanceColour(b)).norm(), 0.08f) << "ids " << a << " and " << b;
    }
  }
  EXPECT_EQ(InstanceColour(5), InstanceColour(5));
}

TEST(CloudColoursTest, ParsesModesAndRejectsOthersNamingTheOption) {
  EXPECT_EQ(*ParseColourMode("normal"), ColourMode::kNormal);
  EXPECT_EQ(*ParseColourMode("height"), ColourMode::kHeight);
  EXPECT_EQ(*ParseColourMode("status"), ColourMode::kStatus);
  const auto bad = ParseColourMode("rainbow");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad.status().message().rfind("--color", 0), 0u) << bad.status().message();
}

TEST(CloudColoursTest, EveryPointStatusHasItsOwnColour) {
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldStatus;
  for (uint8_t s = 1; s <= static_cast<uint8_t>(PointStatus::kRejectedUnlit); ++s) {
    cloud.positions.emplace_back(s, 0, 0);
    cloud.statuses.push_back(s);
  }
  const auto colours = *CloudColours(cloud, ColourMode::kStatus, View{});
  ASSERT_EQ(colours.size(), cloud.size());
  for (size_t i = 0; i < colours.size(); ++i) {
    EXPECT_EQ(colours[i], StatusColour(cloud.statuses[i]));
    EXPECT_GT(colours[i].maxCoeff(), 0.2f) << "status " << int(cloud.statuses[i]);
    for (size_t j = 0; j < i; ++j) EXPECT_GT((colours[i] - colours[j]).norm(), 0.2f) << i << " vs " << j;
  }
  EXPECT_EQ(StatusColour(0), Eigen::Vector3f::Zero());
}

TEST(CloudColoursTest, MissingFieldNamesTheOptionAndTheField) {
  PointCloud cloud;
  cloud.positions = {{0, 0, 0}, {1, 0, 0}};
  const View view;
  for (const auto& [mode, field] : {std::pair{ColourMode::kIntensity, "intensity"},
                                    std::pair{ColourMode::kInstance, "instance"},
                                    std::pair{ColourMode::kNormal, "normal"},
                                    std::pair{ColourMode::kStatus, "status"}}) {
    const auto colours = CloudColours(cloud, mode, view);
    ASSERT_FALSE(colours.ok()) << field;
    EXPECT_EQ(colours.status().code(), StatusCode::kFailedPrecondition);
    EXPECT_NE(colours.status().message().find("--color"), std::string::npos) << colours.status().message();
    EXPECT_NE(colours.status().message().find(field), std::string::npos) << colours.status().message();
  }
  EXPECT_TRUE(CloudColours(cloud, ColourMode::kDepth, view).ok());
  EXPECT_TRUE(CloudColours(cloud, ColourMode::kHeight, view).ok());
}

TEST(CloudColoursTest, FieldsMapAsDocumented) {
  PointCloud cloud;
  cloud.fields = kFieldPosition | kFieldNormal | kFieldIntensity | kFieldInstanceId;
  cloud.positions = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}};
  cloud.normals = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
  cloud.intensities = {0.0f, 0.5f, 2.0f};
  cloud.instance_ids = {0, 3, 3};
  View view;
  view.eye = {0, 0, 10};
  view.up = {0, 0, 1};

  const auto normal = *CloudColours(cloud, ColourMode::kNormal, view);
  EXPECT_TRUE(normal[0].isApprox(Eigen::Vector3f(1, 0.5f, 0.5f)));
  EXPECT_TRUE(normal[1].isApprox(Eigen::Vector3f(0.5f, 0, 0.5f)));
  const auto intensity = *CloudColours(cloud, ColourMode::kIntensity, view);
  EXPECT_FLOAT_EQ(intensity[0].x(), 0.0f);
  EXPECT_FLOAT_EQ(intensity[1].y(), 0.25f);
  EXPECT_FLOAT_EQ(intensity[2].z(), 1.0f);
  const auto instance = *CloudColours(cloud, ColourMode::kInstance, view);
  EXPECT_EQ(instance[0], InstanceColour(0));
  EXPECT_EQ(instance[1], instance[2]);
  // Height along up: lowest 0, highest 1. Depth from the eye at z = 10: the point at z = 2 is nearest.
  const auto height = *CloudColours(cloud, ColourMode::kHeight, view);
  EXPECT_EQ(height[0], Turbo(0));
  EXPECT_EQ(height[1], Turbo(0.5f));
  EXPECT_EQ(height[2], Turbo(1));
  const auto depth = *CloudColours(cloud, ColourMode::kDepth, view);
  EXPECT_EQ(depth[0], Turbo(1));
  EXPECT_EQ(depth[2], Turbo(0));
}

}  // namespace
}  // namespace vscan::render
