// A plan's align, reconstruct and evaluate keys and their option blocks map onto CampaignSpec;
// malformed ones name the line and the key; a server error about them finds its key.

#include <gtest/gtest.h>

#include <string>

#include "campaign/campaign_errors.h"
#include "campaign/campaign_plan.h"
#include "plan_text.h"

namespace vscan::cli {
namespace {

using test::kRoot;
using test::Parse;

// Line numbers below refer to this text (line 1 is "scene_id: s-1").
const std::string kModelPlan = R"(scene_id: s-1
mount_id: m-1
sensor: {preset: ideal}
viewpoints:
  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}
align: true
reconstruct: true
evaluate: true
alignment: {initial_pose: features, voxel_size: 0.002, max_correspondence_distance: 0.01, min_fitness: 0.4,
            skip_pose_graph: true}
reconstruction: {method: POISSON, voxel_size: 0.001, poisson_depth: 9}
evaluation:
  tau: 0.0005
  next_best_views: 4
  skip_next_best_views: false
)";


std::string Replace(const std::string& from, const std::string& to) {
  std::string text = kModelPlan;
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(CampaignPlanModel, KeysMapOntoTheSpec) {
  const auto plan = Parse(kModelPlan);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  const v1::CampaignSpec& spec = plan->spec;
  EXPECT_TRUE(spec.align());
  EXPECT_TRUE(spec.reconstruct());
  EXPECT_TRUE(spec.evaluate());
  EXPECT_EQ(spec.alignment().initial_pose(), v1::INITIAL_POSE_FEATURES);
  EXPECT_EQ(spec.alignment().voxel_size(), 0.002);
  EXPECT_EQ(spec.alignment().max_correspondence_distance(), 0.01);
  EXPECT_EQ(spec.alignment().min_fitness(), 0.4);
  EXPECT_TRUE(spec.alignment().skip_pose_graph());
  EXPECT_EQ(spec.reconstruction().method(), v1::RECONSTRUCTION_METHOD_POISSON);
  EXPECT_EQ(spec.reconstruction().voxel_size(), 0.001);
  EXPECT_EQ(spec.reconstruction().poisson_depth(), 9u);
  EXPECT_EQ(spec.evaluation().tau(), 0.0005);
  EXPECT_EQ(spec.evaluation().next_best_views(), 4u);
  EXPECT_FALSE(spec.evaluation().skip_next_best_views());
}

TEST(CampaignPlanModel, AbsentKeysRunNoModelPart) {
  const auto plan = Parse(R"(scene_id: s-1
mount_id: m-1
sensor: {preset: ideal}
viewpoints:
  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}
)");
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_FALSE(plan->spec.align());
  EXPECT_FALSE(plan->spec.reconstruct());
  EXPECT_FALSE(plan->spec.evaluate());
  EXPECT_FALSE(plan->spec.has_alignment());
}

TEST(CampaignPlanModel, EvaluateAloneTakesAlignmentOptions) {
  // evaluate implies align on the server, so the alignment block is welcome without align.
  const auto plan = Parse(R"(scene_id: s-1
mount_id: m-1
sensor: {preset: ideal}
viewpoints:
  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}
evaluate: true
alignment: {initial_pose: known, voxel_size: 0.002}
)");
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_FALSE(plan->spec.align());
  EXPECT_TRUE(plan->spec.evaluate());
  EXPECT_EQ(plan->spec.alignment().initial_pose(), v1::INITIAL_POSE_KNOWN);
  EXPECT_EQ(plan->spec.alignment().voxel_size(), 0.002);
}

struct BadModelKey {
  const char* name;
  const char* from;
  const char* to;
  const char* message;
};

void PrintTo(const BadModelKey& bad, std::ostream* os) { *os << bad.name; }

class MalformedModelKey : public testing::TestWithParam<BadModelKey> {};

TEST_P(MalformedModelKey, NamesLineAndKey) {
  const BadModelKey& bad = GetParam();
  const auto plan = Parse(Replace(bad.from, bad.to));
  ASSERT_FALSE(plan.ok()) << bad.to;
  EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(plan.status().message().starts_with(bad.message))
      << "got:      " << plan.status().message() << "\nexpected: " << bad.message;
}

INSTANTIATE_TEST_SUITE_P(
    CampaignPlanModel, MalformedModelKey,
    testing::Values(
        BadModelKey{"non_bool", "align: true", "align: often", "plan.yaml:6: align: expected true or false"},
        BadModelKey{"unknown_initial_pose", "initial_pose: features", "initial_pose: guess",
                    "plan.yaml:9: alignment.initial_pose: unknown value 'guess' (known, features)"},
        BadModelKey{"unspecified_is_no_value", "method: POISSON", "method: unspecified",
                    "plan.yaml:11: reconstruction.method: unknown value 'unspecified' (tsdf, poisson)"},
        BadModelKey{"unknown_option", "poisson_depth: 9", "depth: 9",
                    "plan.yaml:11: reconstruction.depth: unknown key (expected one of method, voxel_size, "
                    "poisson_depth)"},
        BadModelKey{"negative_views", "next_best_views: 4", "next_best_views: -1",
                    "plan.yaml:14: evaluation.next_best_views: must be between 0 and"},
        BadModelKey{"block_without_its_part", "evaluate: true", "evaluate: false",
                    "plan.yaml:12: evaluation: tunes a part that does not run: set evaluate: true"},
        BadModelKey{"reconstruction_without_reconstruct", "reconstruct: true", "reconstruct: false",
                    "plan.yaml:11: reconstruction: tunes a part that does not run: set reconstruct: true"}),
    [](const testing::TestParamInfo<BadModelKey>& info) { return info.param.name; });

TEST(CampaignPlanModel, ServerErrorsFindTheirKey) {
  const auto plan = Parse(kModelPlan);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(LocateInPlan(*plan, PlanCall::kStartCampaign,
                         InvalidArgument("spec.evaluation.next_best_views", "at most 20")),
            "plan.yaml:14: evaluation.next_best_views: at most 20");
  EXPECT_EQ(LocateInPlan(*plan, PlanCall::kStartCampaign,
                         InvalidArgument("spec.alignment.voxel_size", "must be below 0.1 m")),
            "plan.yaml:9: alignment.voxel_size: must be below 0.1 m");
}

}  // namespace
}  // namespace vscan::cli
