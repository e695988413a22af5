// Materials and the returned light in the plans that scan: a campaign's objects and its scans, a
// dataset's part types (one material or a seeded choice per scene) and its scans. One reader of a
// material (vscan/plan/bin_fill_plan.h) serves bin, campaign and dataset plans.

#include <google/protobuf/descriptor.h>
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "plan_text.h"
#include "service/datasets/format/dataset_materials.h"
#include "service/datasets/dataset_job_shard.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "vscan/plan/bin_fill_plan.h"
#include "vscan/plan/returned_light_plan.h"
#include "vscan/v1/sensor.pb.h"

namespace vscan {
namespace {

using cli::test::Parse;

// Line 5 holds the object's material, line 10 returned_light.
const std::string kCampaign = R"(scene:
  objects:
    - mesh: data/meshes/bunny/bunny_zipper_res2.ply
      unit: mm
      material: black-anodised-aluminium
    - {mesh: data/meshes/bunny/bunny_zipper_res2.ply, unit: mm, material: {diffuse_albedo: 0.3, metallic: 0, roughness: 0.6, specular_reflectance: 0.05}}
    - {mesh: data/meshes/bunny/bunny_zipper_res2.ply, unit: mm}
mount_id: m-1
sensor: {preset: ideal}
returned_light: {emitter_w_per_sr: 0.002, exposure_s: 0.02}
viewpoints:
  - {position: [1, 0, 0.5], target: [0, 0, 0]}
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(CampaignPlanMaterials, ObjectsCarryTheirMaterialsAndTheSpecTheLight) {
  // mount_id with a scene to build is refused; the objects are read first, so use scene_id-less text.
  const auto plan = Parse(Replace(kCampaign, "mount_id: m-1\n", "robot: {bundle: data/robots/ur5}\n"));
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  const auto& objects = plan->scene->objects;
  ASSERT_EQ(objects.size(), 3u);
  EXPECT_EQ(objects[0].material->preset(), "black-anodised-aluminium");
  EXPECT_FALSE(objects[0].material->has_values());
  EXPECT_EQ(objects[1].material->values().roughness(), 0.6);
  EXPECT_EQ(objects[1].material->values().specular_reflectance(), 0.05);
  EXPECT_FALSE(objects[2].material.has_value());
  ASSERT_TRUE(plan->spec.has_returned_light());
  EXPECT_EQ(plan->spec.returned_light().emitter_w_per_sr(), 0.002);
  EXPECT_EQ(plan->spec.returned_light().exposure_s(), 0.02);
  EXPECT_EQ(plan->spec.returned_light().min_snr(), 0.0);  // the server's default
  EXPECT_EQ(plan->key_marks.at("scene.objects[0].material").line + 1, 5);
}

TEST(CampaignPlanMaterials, AnEmptyLightBlockTakesEveryDefaultAndNoBlockNoLight) {
  const std::string robot = Replace(kCampaign, "mount_id: m-1\n", "robot: {bundle: data/robots/ur5}\n");
  const auto defaults = Parse(Replace(robot, "returned_light: {emitter_w_per_sr: 0.002, exposure_s: 0.02}",
                                      "returned_light: {}"));
  ASSERT_TRUE(defaults.ok()) << defaults.status().message();
  EXPECT_TRUE(defaults->spec.has_returned_light());
  const auto none = Parse(Replace(robot, "returned_light: {emitter_w_per_sr: 0.002, exposure_s: 0.02}\n", ""));
  ASSERT_TRUE(none.ok()) << none.status().message();
  EXPECT_FALSE(none->spec.has_returned_light());
}

TEST(CampaignPlanMaterials, RefusalsNameTheKeyAndLine) {
  const std::string robot = Replace(kCampaign, "mount_id: m-1\n", "robot: {bundle: data/robots/ur5}\n");
  const std::pair<std::pair<std::string, std::string>, std::string> cases[] = {
      {{"material: black-anodised-aluminium", "material: {choose: [white-abs, black-abs]}"},
       "plan.yaml:5: scene.objects[0].material: a campaign's object has one material; choose is for dataset plans"},
      {{"material: black-anodised-aluminium", "material: {diffuse_albedo: 0.3}"},
       "plan.yaml:5: scene.objects[0].material.metallic: required"},
      {{"material: black-anodised-aluminium", "material: {colour: red}"},
       "plan.yaml:5: scene.objects[0].material.colour: unknown key"},
      {{"roughness: 0.6", "roughness: 1.5"}, "plan.yaml:6: scene.objects[1].material.roughness: must be within (0, 1]"},
      {{"roughness: 0.6", "roughness: 0"}, "plan.yaml:6: scene.objects[1].material.roughness: must be within (0, 1]"},
      {{"metallic: 0,", "metallic: -0.5,"}, "plan.yaml:6: scene.objects[1].material.metallic: must be within [0, 1]"},
      {{"roughness: 0.6", "roughness: .nan"}, "plan.yaml:6: scene.objects[1].material.roughness: '.nan' is not finite"},
      {{"exposure_s: 0.02", "exposure: 0.02"}, "plan.yaml:10: returned_light.exposure: unknown key"},
      {{"exposure_s: 0.02", "exposure_s: .inf"}, "plan.yaml:10: returned_light.exposure_s: '.inf' is not finite"},
      {{"returned_light: {emitter_w_per_sr: 0.002, exposure_s: 0.02}", "returned_light: bright"},
       "plan.yaml:10: returned_light: expected a mapping"},
  };
  for (const auto& [edit, message] : cases) {
    const auto plan = Parse(Replace(robot, edit.first, edit.second));
    ASSERT_FALSE(plan.ok()) << edit.second;
    EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(plan.status().message().starts_with(message))
        << "got:      " << plan.status().message() << "\nexpected: " << message;
  }
}

// The dataset plan's proto-free reader takes exactly the message's keys.
TEST(ReturnedLightPlan, KeysAreTheMessagesFields) {
  const auto* descriptor = v1::ReturnedLight::descriptor();
  ASSERT_EQ(static_cast<size_t>(descriptor->field_count()), std::size(plan::kReturnedLightKeys));
  for (int i = 0; i < descriptor->field_count(); ++i) {
    EXPECT_EQ(descriptor->field(i)->name(), plan::kReturnedLightKeys[i]);
  }
}

StatusOr<service::dataset::DatasetPlan> Dataset(const std::string& material, const std::string& extra = "") {
  return service::dataset::ParseDatasetPlanYaml(
      "bins:\n"
      "  - name: b\n"
      "    bin: {inner_size: [0.3, 0.2, 0.1]}\n"
      "    parts:\n"
      "      - {mesh_id: m-1, count: 2}\n"
      "      - mesh_id: m-2\n"
      "        count: 3\n"
      "        material: " + material + "\n"
      "seeds: [1]\nsensors: [s]\n" + extra,
      "plan");
}

TEST(DatasetPlanMaterials, OneMaterialOrAChoiceOfSeveral) {
  const auto one = Dataset("white-abs");
  ASSERT_TRUE(one.ok()) << one.status().message();
  EXPECT_TRUE(one->bin_fills[0].parts[0].materials.empty());
  ASSERT_EQ(one->bin_fills[0].parts[1].materials.size(), 1u);
  EXPECT_EQ(one->bin_fills[0].parts[1].materials[0].preset, "white-abs");
  const auto choice = Dataset(
      "{choose: [machined-aluminium, black-anodised-aluminium, {diffuse_albedo: 0.2, metallic: 0, roughness: 0.5, "
      "specular_reflectance: 0.04}]}");
  ASSERT_TRUE(choice.ok()) << choice.status().message();
  const auto& materials = choice->bin_fills[0].parts[1].materials;
  ASSERT_EQ(materials.size(), 3u);
  EXPECT_EQ(materials[1].preset, "black-anodised-aluminium");
  EXPECT_EQ(materials[2].diffuse_albedo, 0.2);
  EXPECT_FALSE(choice->returned_light.has_value());
  const auto lit = Dataset("white-abs", "returned_light: {emitter_w_per_sr: 0.5, min_snr: 3}\n");
  ASSERT_TRUE(lit.ok()) << lit.status().message();
  ASSERT_TRUE(lit->returned_light.has_value());
  EXPECT_EQ(lit->returned_light->emitter_w_per_sr, 0.5);
  EXPECT_EQ(lit->returned_light->min_snr, 3.0);
  EXPECT_EQ(lit->returned_light->exposure_s, 0.0);
}

TEST(DatasetPlanMaterials, RefusalsNameTheKeyAndLine) {
  const std::pair<std::string, std::string> cases[] = {
      {"unobtainium", "plan:8: bins[0].parts[1].material: unknown preset 'unobtainium' (matte-grey, white-abs"},
      {"{choose: [white-abs, unobtainium]}",
       "plan:8: bins[0].parts[1].material.choose[1]: unknown preset 'unobtainium'"},
      {"{choose: []}", "plan:8: bins[0].parts[1].material.choose: expected at least 1 items"},
      {"{choose: white-abs}", "plan:8: bins[0].parts[1].material.choose: expected a list"},
      {"{choose: [white-abs], weights: [1]}", "plan:8: bins[0].parts[1].material.weights: unknown key"},
      {"{diffuse_albedo: .nan, metallic: 0, roughness: 0.5, specular_reflectance: 0.04}",
       "plan:8: bins[0].parts[1].material.diffuse_albedo: '.nan' is not finite"},
      {"{diffuse_albedo: -0.1, metallic: 0, roughness: 0.5, specular_reflectance: 0.04}",
       "plan:8: bins[0].parts[1].material.diffuse_albedo: must be within [0, 1]"},
  };
  for (const auto& [material, message] : cases) {
    const auto plan = Dataset(material);
    ASSERT_FALSE(plan.ok()) << material;
    EXPECT_EQ(plan.status().code(), StatusCode::kInvalidArgument);
    EXPECT_TRUE(plan.status().message().starts_with(message))
        << "got:      " << plan.status().message() << "\nexpected: " << message;
  }
  const auto light = Dataset("white-abs", "returned_light: {exposure_s: -1}\n");
  ASSERT_FALSE(light.ok());
  EXPECT_TRUE(light.status().message().starts_with("plan:11: returned_light.exposure_s: must not be negative"))
      << light.status().message();
}

TEST(DatasetPlanMaterials, TheExamplePlanReads) {
  const auto plan = service::ReadDatasetPlanFile(std::string(VSCAN_SOURCE_DIR) + "/examples/datasets/lit_parts.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->bin_fills[0].parts[0].materials.size(), 3u);
  EXPECT_EQ(plan->bin_fills[0].parts[1].materials.at(0).preset, "polished-steel");
  ASSERT_TRUE(plan->returned_light.has_value());
}

// A million choices are refused by their count, before any is read.
TEST(DatasetPlanMaterials, AHugeChoiceListIsRefusedByItsSize) {
  std::string list = "{choose: [white-abs";
  for (int i = 0; i < 1000000; ++i) list += ", white-abs";
  list += "]}";
  const auto plan = Dataset(list);
  ASSERT_FALSE(plan.ok());
  EXPECT_NE(plan.status().message().find("material.choose: at most 64 materials, got 1000001"), std::string::npos)
      << plan.status().message().substr(0, 200);
}

// The same seed gives the same choice, and over many scenes every option is taken about as often.
TEST(DatasetMaterialChoice, DeterministicAndCoversEveryOption) {
  constexpr size_t kOptions = 3;
  std::map<size_t, int> taken;
  bool differs_by_bin = false, differs_by_part = false;
  for (uint64_t seed = 0; seed < 3000; ++seed) {
    const size_t index = service::dataset::PartMaterialIndex(seed, 0, 1, kOptions);
    ASSERT_LT(index, kOptions);
    EXPECT_EQ(index, service::dataset::PartMaterialIndex(seed, 0, 1, kOptions));
    ++taken[index];
    differs_by_bin = differs_by_bin || index != service::dataset::PartMaterialIndex(seed, 1, 1, kOptions);
    differs_by_part = differs_by_part || index != service::dataset::PartMaterialIndex(seed, 0, 2, kOptions);
  }
  ASSERT_EQ(taken.size(), kOptions);
  // 1000 expected each; 5 sigma of a binomial(3000, 1/3) is about 130.
  for (const auto& [index, count] : taken) EXPECT_NEAR(count, 1000, 130) << index;
  EXPECT_TRUE(differs_by_bin);
  EXPECT_TRUE(differs_by_part);
  EXPECT_EQ(service::dataset::PartMaterialIndex(7, 0, 0, 1), 0u);
  EXPECT_EQ(service::dataset::PartMaterialIndex(7, 0, 0, 0), 0u);
}

TEST(DatasetMaterialChoice, SceneMaterialsJsonNamesEachInstance) {
  plan::MaterialPlan values;
  values.diffuse_albedo = 0.25;
  values.roughness = 0.5;
  const std::string json = service::dataset::SceneMaterialsJson(
      {{2, 1, "block", plan::MaterialPlan{"white-abs", 0, 0, 0, 0}}, {3, 2, "pin", values}});
  EXPECT_NE(json.find("\"instance_id\":2,\"obj_id\":1,\"part\":\"block\",\"material\":{\"preset\":\"white-abs\"}"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"instance_id\":3,\"obj_id\":2,\"part\":\"pin\",\"material\":{\"diffuse_albedo\":0.25"),
            std::string::npos)
      << json;
}

}  // namespace
}  // namespace vscan
