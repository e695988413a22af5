// Server errors traced back to the plan: the field a call's message names becomes the plan's
// file, line and key; failures that name no field of the plan stay server errors.

#include "campaign/campaign_errors.h"
#include "plan_text.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>

namespace vscan::cli {
namespace {

using test::kRoot;

// Line numbers below refer to this text.
const std::string kErrorsPlan = R"(name: errors
scene:
  objects:
    - mesh: data/meshes/bunny/bunny_zipper_res2.ply
      unit: m
    - mesh: data/meshes/bunny/bunny_zipper_res2.ply
      unit: m
      pose: {xyz: [0.2, 0, 0]}
  table: {axis: [0, 0, 1]}
robot:
  bundle: data/robots/ur5
  encoder_sigma: 0.001
sensor:
  pinhole: {width: 320, height: 240, horizontal_fov_deg: 50, near: 0.1, far: 3}
viewpoints:
  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}
  - position: [-0.4, 0, 0.3]
    target: [0, 0, 0.05]
rotations: 4
)";

struct Case {
  const char* name;
  PlanCall call;
  size_t object;
  Status status;
  // The whole message, or nullopt: not the plan's fault.
  std::optional<std::string> expected;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class LocateInPlanTest : public testing::TestWithParam<Case> {};

TEST_P(LocateInPlanTest, NamesFileLineAndKey) {
  const auto plan = ParseCampaignPlan(kErrorsPlan, "plan.yaml", kRoot);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  const Case& c = GetParam();
  EXPECT_EQ(LocateInPlan(*plan, c.call, c.status, c.object), c.expected);
}

INSTANTIATE_TEST_SUITE_P(
    CampaignErrors, LocateInPlanTest,
    testing::Values(
        Case{"rotations", PlanCall::kStartCampaign, 0, InvalidArgument("spec.rotations: at most 3600"),
             "plan.yaml:19: rotations: at most 3600"},
        Case{"sensor_width", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.sensor.pinhole.width: must be positive"),
             "plan.yaml:14: sensor.pinhole.width: must be positive"},
        // A field the plan does not write stands at the nearest key it does.
        Case{"derived_focal_length", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.sensor.pinhole.fx: must be between 0.01 and 1e8 pixels"),
             "plan.yaml:14: sensor.pinhole.fx: must be between 0.01 and 1e8 pixels"},
        Case{"two_fields", PlanCall::kStartCampaign, 0,
             ResourceExhausted("spec.sensor.pinhole.width x sensor.pinhole.height: 48000000 rays exceed the "
                               "limit of 16777216"),
             "plan.yaml:14: sensor.pinhole.width x sensor.pinhole.height: 48000000 rays exceed the limit of "
             "16777216"},
        Case{"block_viewpoint", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.viewpoints[1].target: coordinates beyond 10 km"),
             "plan.yaml:18: viewpoints[1].target: coordinates beyond 10 km"},
        Case{"missing_up", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.viewpoints[0].up: must not be zero or parallel to the view direction"),
             "plan.yaml:16: viewpoints[0].up: must not be zero or parallel to the view direction"},
        // rotation_step_deg left out: the step comes from rotations.
        Case{"defaulted_step", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.rotation_step_deg: must be finite and within +-360"),
             "plan.yaml:19: rotation_step_deg: must be finite and within +-360"},
        Case{"unset_field_at_top", PlanCall::kStartCampaign, 0,
             InvalidArgument("spec.fields: normal estimation needs normals"),
             "plan.yaml:1: fields: normal estimation needs normals"},
        Case{"not_found_preset", PlanCall::kStartCampaign, 0, NotFound("spec.sensor.preset: no preset 'x'"),
             "plan.yaml:13: sensor.preset: no preset 'x'"},
        Case{"scene_precondition", PlanCall::kStartCampaign, 0,
             FailedPrecondition("spec.rotations: scene 's' has no rotary table enabled to turn"),
             "plan.yaml:19: rotations: scene 's' has no rotary table enabled to turn"},
        Case{"object_pose", PlanCall::kAddObject, 1, InvalidArgument("pose.translation: NaN or infinite value"),
             "plan.yaml:8: scene.objects[1].pose.translation: NaN or infinite value"},
        Case{"table_axis", PlanCall::kSetRotaryTable, 0, InvalidArgument("table.axis: zero vector"),
             "plan.yaml:9: scene.table.axis: zero vector"},
        Case{"encoder_sigma", PlanCall::kMountRobot, 0,
             InvalidArgument("encoder_sigma: expected 1 or 6 values (one per joint of robot 'r'), got 7"),
             "plan.yaml:12: robot.encoder_sigma: expected 1 or 6 values (one per joint of robot 'r'), got 7"},
        Case{"scene_name", PlanCall::kCreateScene, 0, InvalidArgument("name: longer than 256 bytes"),
             "plan.yaml:2: scene.name: longer than 256 bytes"},
        // Not the plan's fault.
        Case{"unavailable", PlanCall::kStartCampaign, 0, Unavailable("server is shutting down"), std::nullopt},
        Case{"queue_full", PlanCall::kStartCampaign, 0,
             ResourceExhausted("spec: 64 jobs already wait to run; retry later"), std::nullopt},
        Case{"internal", PlanCall::kMountRobot, 0, Status(StatusCode::kInternal, "encoder_sigma: oops"),
             std::nullopt},
        Case{"no_field", PlanCall::kCreateScene, 0, InvalidArgument("the catalogue is read-only now"),
             std::nullopt},
        Case{"other_call_prefix", PlanCall::kSetRotaryTable, 0, NotFound("scene_id: no scene 's'"), std::nullopt}),
    [](const testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace vscan::cli
