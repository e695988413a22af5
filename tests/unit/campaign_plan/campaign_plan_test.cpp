// Campaign plans: a full plan maps to the expected messages; every malformed plan is rejected
// with the file, the line and the key path of the offending value.

#include "campaign/campaign_plan.h"

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "plan_text.h"
#include "vscan/common/proto_convert.h"

namespace vscan::cli {
namespace {

using test::kRoot;
using test::Parse;

using google::protobuf::util::MessageDifferencer;


// Line numbers below refer to this text (line 1 is "name: test-plan").
const std::string kPlan = R"(name: test-plan
scene:
  name: desk
  objects:
    - mesh: data/meshes/bunny/bunny_zipper_res2.ply
      unit: mm
      scale: 2
      label: bunny
      on_table: true
      pose: {xyz: [0.1, 0, 0], rpy_deg: [90, 0, 0]}
  table: {centre: [0, 0, 0.01], axis: [0, 0, 2], angle_deg: 15}
robot:
  bundle: data/robots/ur5
  urdf: ur5_robot.urdf
  base_link: base_link
  tip_link: tool0
  base_pose: {xyz: [-0.5, 0, 0], rpy_deg: [0, 0, 90]}
  tool_offset: {xyz: [0, 0, 0.05]}
  encoder_sigma: [0.001, 0.002, 0.001, 0.001, 0.001, 0.001]
sensor:
  pinhole: {width: 320, height: 240, horizontal_fov_deg: 50, near: 0.1, far: 3}
noise: {sigma_a: 0.001, along_ray: true}
backend: depth
fields: [normal, range]
frame: sensor
viewpoints:
  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}
  - {position: [0, 0.4, 0.3], target: [0, 0, 0.05], up: [0, 0, 1]}
  - position: [-0.4, 0, 0.3]
    target: [0, 0, 0.05]
rotations: 4
rotation_step_deg: 30
start_angle_deg: 10
seed: 18446744073709551615
apply_encoder_noise: true
reject_collisions: true
)";


// kPlan with the first line that starts with `from` (after indentation) replaced by `to`.
std::string Edit(const std::string& from, const std::string& to, std::string text = kPlan) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

v1::Vector3 V(double x, double y, double z) { return ToProto(Eigen::Vector3d(x, y, z)); }

TEST(CampaignPlan, FullPlanMapsToSpecSceneAndMount) {
  const auto plan = Parse(kPlan);
  ASSERT_TRUE(plan.ok()) << plan.status().message();

  v1::CampaignSpec spec;
  spec.set_name("test-plan");
  spec.mutable_sensor()->mutable_pinhole()->set_width(320);
  spec.mutable_sensor()->mutable_pinhole()->set_height(240);
  spec.mutable_sensor()->mutable_pinhole()->set_horizontal_fov_deg(50);
  spec.mutable_sensor()->mutable_pinhole()->set_near(0.1);
  spec.mutable_sensor()->mutable_pinhole()->set_far(3);
  spec.mutable_noise()->set_sigma_a(0.001);
  spec.mutable_noise()->set_along_ray(true);
  spec.set_backend(v1::SCAN_BACKEND_RASTER_DEPTH);
  spec.add_fields(v1::POINT_FIELD_POSITION);
  spec.add_fields(v1::POINT_FIELD_NORMAL);
  spec.add_fields(v1::POINT_FIELD_RANGE);
  spec.set_frame(v1::FRAME_SENSOR);
  for (const auto& position : {V(0.4, 0, 0.3), V(0, 0.4, 0.3), V(-0.4, 0, 0.3)}) {
    auto* viewpoint = spec.add_viewpoints();
    *viewpoint->mutable_position() = position;
    *viewpoint->mutable_target() = V(0, 0, 0.05);
  }
  *spec.mutable_viewpoints(1)->mutable_up() = V(0, 0, 1);
  spec.set_rotations(4);
  spec.set_rotation_step_deg(30);
  spec.set_start_angle_deg(10);
  spec.set_seed(18446744073709551615ull);
  spec.set_apply_encoder_noise(true);
  spec.set_reject_collisions(true);
  std::string diff;
  MessageDifferencer differ;
  differ.ReportDifferencesToString(&diff);
  EXPECT_TRUE(differ.Compare(spec, plan->spec)) << diff;

  ASSERT_TRUE(plan->scene.has_value());
  EXPECT_EQ(plan->scene->name, "desk");
  ASSERT_EQ(plan->scene->objects.size(), 1u);
  const PlanObject& bunny = plan->scene->objects[0];
  EXPECT_EQ(bunny.mesh, kRoot / "data/meshes/bunny/bunny_zipper_res2.ply");
  EXPECT_EQ(bunny.unit, v1::LENGTH_UNIT_MILLIMETRE);
  EXPECT_EQ(bunny.scale, 2.0);
  EXPECT_EQ(bunny.label, "bunny");
  EXPECT_TRUE(bunny.on_table);
  ASSERT_TRUE(bunny.pose.has_value());
  const auto bunny_pose = PoseFromProto(*bunny.pose, "pose");
  ASSERT_TRUE(bunny_pose.ok());
  // Roll 90 degrees: +y goes to +z.
  EXPECT_TRUE(bunny_pose->translation().isApprox(Eigen::Vector3d(0.1, 0, 0)));
  EXPECT_TRUE((bunny_pose->linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  ASSERT_TRUE(plan->scene->table.has_value());
  EXPECT_TRUE(plan->scene->table->enabled());
  EXPECT_TRUE(MessageDifferencer::Equals(plan->scene->table->axis(), V(0, 0, 1)));
  EXPECT_TRUE(MessageDifferencer::Equals(plan->scene->table->centre(), V(0, 0, 0.01)));
  EXPECT_EQ(plan->scene->table->angle_deg(), 15);

  ASSERT_TRUE(plan->robot.has_value());
  EXPECT_EQ(plan->robot->bundle, kRoot / "data/robots/ur5");
  EXPECT_EQ(plan->robot->urdf, "ur5_robot.urdf");
  EXPECT_EQ(plan->robot->base_link, "base_link");
  EXPECT_EQ(plan->robot->tip_link, "tool0");
  const auto base = PoseFromProto(plan->robot->mount.base_pose(), "base_pose");
  ASSERT_TRUE(base.ok());
  // Yaw 90 degrees: +x goes to +y.
  EXPECT_TRUE(base->translation().isApprox(Eigen::Vector3d(-0.5, 0, 0)));
  EXPECT_TRUE((base->linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  const auto tool = PoseFromProto(plan->robot->mount.tool_offset(), "tool_offset");
  ASSERT_TRUE(tool.ok());
  EXPECT_TRUE(tool->isApprox(Pose3(Eigen::Translation3d(0, 0, 0.05))));
  ASSERT_EQ(plan->robot->mount.encoder_sigma_size(), 6);
  EXPECT_EQ(plan->robot->mount.encoder_sigma(1), 0.002);
  EXPECT_FALSE(plan->robot->mount.links_visible());
  EXPECT_TRUE(plan->scene_id.empty());
  EXPECT_TRUE(plan->mount_id.empty());
}

TEST(CampaignPlan, ExistingIdsPresetAndDefaults) {
  const auto plan = Parse(R"(scene_id: s-1
mount_id: m-1
sensor: {preset: kinect-v1-class}
viewpoints:
  - {position: [1, 0, 0.5], target: [0, 0, 0]}
rotations: 8
)");
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->name, "plan");  // the file's stem
  EXPECT_EQ(plan->scene_id, "s-1");
  EXPECT_EQ(plan->mount_id, "m-1");
  EXPECT_FALSE(plan->scene.has_value());
  EXPECT_FALSE(plan->robot.has_value());
  EXPECT_EQ(plan->spec.sensor().preset(), "kinect-v1-class");
  // No noise key: the preset's own noise applies.
  EXPECT_FALSE(plan->spec.has_noise());
  EXPECT_EQ(plan->spec.rotations(), 8u);
  EXPECT_DOUBLE_EQ(plan->spec.rotation_step_deg(), 45.0);
  EXPECT_EQ(plan->spec.backend(), v1::SCAN_BACKEND_RAYCAST);
  EXPECT_EQ(plan->spec.frame(), v1::FRAME_WORLD);
  EXPECT_EQ(plan->spec.fields_size(), 0);
}

TEST(CampaignPlan, PoseForms) {
  const std::string text = Edit("base_pose: {xyz: [-0.5, 0, 0], rpy_deg: [0, 0, 90]}",
                                "base_pose: {look_at: {eye: [1, 0, 0], target: [0, 0, 0]}}");
  const auto plan =
      Parse(Edit("tool_offset: {xyz: [0, 0, 0.05]}", "tool_offset: {xyz: [0, 0, 1], quat: [0, 1, 0, 0]}", text));
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->robot->mount.base_pose().kind_case(), v1::Pose::kLookAt);
  const auto tool = PoseFromProto(plan->robot->mount.tool_offset(), "tool_offset");
  ASSERT_TRUE(tool.ok());
  EXPECT_TRUE(tool->translation().isApprox(Eigen::Vector3d(0, 0, 1)));
  // Half a turn about x.
  EXPECT_TRUE((tool->linear() * Eigen::Vector3d::UnitZ()).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
}

// Values only the server's rules judge parse here; `vscan campaign run` asks the server about them
// (validate_only) before it uploads anything.
TEST(CampaignPlan, ServerBoundsAreLeftToTheServer) {
  const std::string down = Edit("- {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}",
                                "- {position: [0, 0, 0.5], target: [0, 0, 0.05]}");
  const auto plan = Parse(Edit("rotations: 4", "rotations: 5000", down));
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->spec.rotations(), 5000u);
  // Straight down without `up`: the arm chooses the turn about the view axis; no up to be parallel.
  EXPECT_FALSE(plan->spec.viewpoints(0).has_up());
}

TEST(CampaignPlan, KnowsTheLineOfEveryKey) {
  const auto plan = Parse(kPlan);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->source, "plan.yaml");
  const std::pair<const char*, int> lines[] = {{"", 1},
                                               {"scene.objects[0].pose", 10},
                                               {"scene.table.axis", 11},
                                               {"robot.encoder_sigma", 19},
                                               {"sensor.pinhole.width", 21},
                                               {"viewpoints[2]", 29},
                                               {"viewpoints[2].target", 30},
                                               {"rotations", 31}};
  for (const auto& [key, line] : lines) {
    ASSERT_TRUE(plan->key_marks.contains(key)) << key;
    EXPECT_EQ(plan->key_marks.at(key).line + 1, line) << key;
  }
}

struct BadPlan {
  std::string name;
  std::string from;
  std::string to;
  // The whole expected prefix, "plan.yaml:LINE: path: what".
  std::string message;
};

void PrintTo(const BadPlan& bad, std::ostream* os) { *os << bad.name; }

class MalformedPlan : public testing::TestWithParam<BadPlan> {};

TEST_P(MalformedPlan, NamesLineAndPath) {
  const BadPlan& bad = GetParam();
  const auto plan = Parse(Edit(bad.from, bad.to));
  ASSERT_FALSE(plan.ok()) << bad.to;
  EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(plan.status().message().starts_with(bad.message))
      << "got:      " << plan.status().message() << "\nexpected: " << bad.message;
}

INSTANTIATE_TEST_SUITE_P(
    CampaignPlan, MalformedPlan,
    testing::Values(
        BadPlan{"short_target", "- position: [-0.4, 0, 0.3]\n    target: [0, 0, 0.05]",
                "- position: [-0.4, 0, 0.3]\n    target: [0, 0]",
                "plan.yaml:30: viewpoints[2].target: expected 3 numbers, got 2 items"},
        BadPlan{"look_at_eye_on_target", "base_pose: {xyz: [-0.5, 0, 0], rpy_deg: [0, 0, 90]}",
                "base_pose: {look_at: {eye: [1, 0, 0], target: [1, 0, 0]}}",
                "plan.yaml:17: robot.base_pose.look_at: eye and target coincide"},
        BadPlan{"unknown_key", "rotations: 4", "rotation: 4", "plan.yaml:31: rotation: unknown key"},
        BadPlan{"zero_rotations", "rotations: 4", "rotations: 0", "plan.yaml:31: rotations: must be between 1 and"},
        BadPlan{"fractional_rotations", "rotations: 4", "rotations: 2.5",
                "plan.yaml:31: rotations: '2.5' is not a whole number"},
        BadPlan{"negative_seed", "seed: 18446744073709551615", "seed: -3", "plan.yaml:34: seed: must be between 0 and"},
        BadPlan{"seed_above_64_bits", "seed: 18446744073709551615", "seed: 18446744073709551616",
                "plan.yaml:34: seed: must be a whole number between 0 and 18446744073709551615"},
        BadPlan{"unknown_unit", "unit: mm", "unit: parsec",
                "plan.yaml:6: scene.objects[0].unit: unknown unit 'parsec'"},
        BadPlan{"missing_unit", "      unit: mm\n", "", "plan.yaml:5: scene.objects[0].unit: required"},
        BadPlan{"missing_mesh_file", "bunny_zipper_res2.ply", "no_such_mesh.ply",
                "plan.yaml:5: scene.objects[0].mesh: no such file or directory"},
        BadPlan{"negative_scale", "scale: 2", "scale: -1", "plan.yaml:7: scene.objects[0].scale: must be positive"},
        BadPlan{"non_bool", "on_table: true", "on_table: maybe",
                "plan.yaml:9: scene.objects[0].on_table: expected true or false"},
        BadPlan{"two_rotation_forms", "rpy_deg: [90, 0, 0]}", "rpy_deg: [90, 0, 0], quat: [1, 0, 0, 0]}",
                "plan.yaml:10: scene.objects[0].pose: give one of rpy_deg, quat, matrix, look_at"},
        BadPlan{"zero_axis", "axis: [0, 0, 2]", "axis: [0, 0, 0]",
                "plan.yaml:11: scene.table.axis: must not be the zero vector"},
        BadPlan{"missing_urdf", "urdf: ur5_robot.urdf", "urdf: nope.urdf",
                "plan.yaml:14: robot.urdf: no file 'nope.urdf'"},
        BadPlan{"negative_sigma", "encoder_sigma: [0.001, 0.002", "encoder_sigma: [-0.001, 0.002",
                "plan.yaml:19: robot.encoder_sigma: must not be negative"},
        BadPlan{"unknown_pose_key", "tool_offset: {xyz: [0, 0, 0.05]}",
                "tool_offset: {xyz: [0, 0, 0.05], rpy: [0, 0, 1]}",
                "plan.yaml:18: robot.tool_offset.rpy: unknown key (expected one of xyz, rpy_deg"},
        BadPlan{"unknown_sensor_key", "horizontal_fov_deg: 50", "horizontal_fov: 50",
                "plan.yaml:21: sensor.pinhole.horizontal_fov: unknown key"},
        BadPlan{"non_numeric_width", "width: 320", "width: wide",
                "plan.yaml:21: sensor.pinhole.width: 'wide' is not a number"},
        BadPlan{"two_sensor_kinds", "sensor:\n  pinhole:", "sensor:\n  preset: ideal\n  pinhole:",
                "plan.yaml:22: sensor.pinhole: conflicts with preset"},
        BadPlan{"list_for_number", "sigma_a: 0.001", "sigma_a: [1]",
                "plan.yaml:22: noise.sigma_a: expected a number, got a list"},
        BadPlan{"unknown_backend", "backend: depth", "backend: laser",
                "plan.yaml:23: backend: unknown backend 'laser'"},
        BadPlan{"unknown_field", "fields: [normal, range]", "fields: [normal, colour]",
                "plan.yaml:24: fields: unknown field 'colour'"},
        BadPlan{"unknown_frame", "frame: sensor", "frame: robot", "plan.yaml:25: frame: unknown frame 'robot'"},
        BadPlan{"duplicate_key", "seed: 18446744073709551615", "seed: 1\nseed: 2", "plan.yaml:35: seed: given twice"},
        BadPlan{"scene_and_scene_id", "name: test-plan", "name: test-plan\nscene_id: abc",
                "plan.yaml:2: scene_id: give either scene or scene_id"},
        BadPlan{"missing_sensor",
                "sensor:\n  pinhole: {width: 320, height: 240, horizontal_fov_deg: 50, near: 0.1, far: 3}\n", "",
                "plan.yaml:1: sensor: required"},
        BadPlan{"empty_viewpoints",
                "viewpoints:\n  - {position: [0.4, 0, 0.3], target: [0, 0, 0.05]}\n"
                "  - {position: [0, 0.4, 0.3], target: [0, 0, 0.05], up: [0, 0, 1]}\n"
                "  - position: [-0.4, 0, 0.3]\n    target: [0, 0, 0.05]\n",
                "viewpoints: []\n", "plan.yaml:26: viewpoints: expected at least 1 items"},
        BadPlan{"yaml_syntax", "noise: {sigma_a: 0.001, along_ray: true}", "noise: {sigma_a: 0.001, along_ray: true",
                "plan.yaml:23: not valid YAML"}),
    [](const testing::TestParamInfo<BadPlan>& info) { return info.param.name; });

TEST(CampaignPlan, TopLevelMustBeAMapping) {
  const auto plan = Parse("- just\n- a list\n");
  ASSERT_FALSE(plan.ok());
  EXPECT_TRUE(plan.status().message().starts_with("plan.yaml:1: a plan is a mapping")) << plan.status().message();
}

TEST(CampaignPlan, UnreadableFileIsNotFound) {
  const auto plan = LoadCampaignPlan((kRoot / "examples/campaigns/no-such-plan.yaml").string());
  ASSERT_FALSE(plan.ok());
  EXPECT_EQ(plan.status().code(), StatusCode::kNotFound);
}

// The shipped examples parse, with paths resolved against their own directory.
TEST(CampaignPlan, ExamplesParse) {
  struct Example {
    const char* file;
    int viewpoints;
    uint32_t rotations;
    double step_deg;
  };
  for (const Example& example : {Example{"bunny_ur5.yaml", 4, 10, 36.0}, Example{"bunny_panda_quick.yaml", 2, 3, 120.0},
                                 Example{"parts_on_table.yaml", 3, 4, 90.0}}) {
    const auto plan = LoadCampaignPlan((kRoot / "examples/campaigns" / example.file).string());
    ASSERT_TRUE(plan.ok()) << example.file << ": " << plan.status().message();
    EXPECT_EQ(plan->spec.viewpoints_size(), example.viewpoints) << example.file;
    EXPECT_EQ(plan->spec.rotations(), example.rotations) << example.file;
    EXPECT_DOUBLE_EQ(plan->spec.rotation_step_deg(), example.step_deg) << example.file;
    ASSERT_TRUE(plan->scene.has_value());
    for (const auto& object : plan->scene->objects) EXPECT_TRUE(std::filesystem::exists(object.mesh)) << example.file;
    ASSERT_TRUE(plan->robot.has_value());
    EXPECT_TRUE(std::filesystem::exists(plan->robot->bundle)) << example.file;
  }
}

}  // namespace
}  // namespace vscan::cli
