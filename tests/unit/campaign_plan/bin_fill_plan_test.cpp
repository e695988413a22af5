// A bin fill is read by one reader (vscan/plan/bin_fill_plan.h) for `vscan bin fill PLAN` and for a
// dataset's bins: the same text gives the same parts and the same refusals through both.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "bins/bin_plan.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "vscan/plan/bin_fill_plan.h"

namespace vscan {
namespace {

class BinFillPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("bin_fill_plan_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "block.stl") << "solid\nendsolid\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // The bin and parts as a bin plan and as a dataset's first bin, both with the fill indented
  // to the same lines' keys.
  StatusOr<cli::BinPlan> AsBinPlan(const std::string& fill) const {
    return cli::ParseBinPlan("scene: s\n" + fill, "p.yaml", dir_);
  }
  StatusOr<service::dataset::DatasetPlan> AsDataset(const std::string& fill) const {
    std::string indented;
    for (size_t at = 0; at < fill.size();) {
      const size_t end = fill.find('\n', at);
      indented += "    " + fill.substr(at, end - at + 1);
      at = end + 1;
    }
    return service::dataset::ParseDatasetPlanYaml("bins:\n  - name: b\n" + indented + "seeds: [1]\nsensors: [s]\n",
                                                  "p.yaml");
  }

  std::filesystem::path dir_;
};

TEST_F(BinFillPlanTest, BothFrontDoorsReadTheSameParts) {
  const std::string fill =
      "bin: {inner_size: [0.3, 0.2, 0.1], wall_thickness: 0.02}\n"
      "parts:\n"
      "  - {mesh: block.stl, unit: inch, count: 3, scale: 2, mass_kg: 0.2, collision: convex_decomposition}\n"
      "  - {mesh_id: m-1, count: 2, name: rod, density_kg_per_m3: 7800}\n";
  const StatusOr<cli::BinPlan> bin = AsBinPlan(fill);
  const StatusOr<service::dataset::DatasetPlan> dataset = AsDataset(fill);
  ASSERT_TRUE(bin.ok()) << bin.status().ToString();
  ASSERT_TRUE(dataset.ok()) << dataset.status().ToString();
  const v1::BinFillSpec& spec = bin->spec;
  const service::dataset::DatasetBinFill& fill_b = dataset->bin_fills.at(0);
  EXPECT_EQ(spec.bin().inner_size().z(), fill_b.inner_size_m.z());
  EXPECT_EQ(spec.bin().wall_thickness(), fill_b.wall_thickness_m);
  ASSERT_EQ(spec.parts_size(), 2);
  ASSERT_EQ(fill_b.parts.size(), 2u);
  EXPECT_EQ(bin->parts[0].unit, v1::LENGTH_UNIT_INCH);
  EXPECT_EQ(fill_b.parts[0].unit, "in");  // the long name read as the short one by both
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(spec.parts(i).count(), fill_b.parts[i].count) << i;
    EXPECT_EQ(spec.parts(i).name(), fill_b.parts[i].name) << i;
    EXPECT_EQ(spec.parts(i).scale() == 0 ? 1.0 : spec.parts(i).scale(), fill_b.parts[i].scale) << i;
  }
  EXPECT_EQ(spec.parts(0).mass_kg(), fill_b.parts[0].mass_kg.value_or(0));
  EXPECT_EQ(spec.parts(1).density_kg_per_m3(), fill_b.parts[1].density_kg_per_m3);
  EXPECT_EQ(spec.parts(0).collision(), v1::PART_COLLISION_CONVEX_DECOMPOSITION);
  EXPECT_EQ(fill_b.parts[0].collision, "convex_decomposition");
  EXPECT_EQ(bin->parts[1].mesh_id, "m-1");
  EXPECT_EQ(fill_b.parts[1].mesh_id, "m-1");
}

// The same mistakes get the same message from both, with the plan's line (the dataset's bin sits
// one line lower).
TEST_F(BinFillPlanTest, BothFrontDoorsRefuseTheSameWay) {
  const std::string bin = "bin: {inner_size: [0.3, 0.2, 0.1]}\n";
  for (const auto& [parts, key, what] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"parts: [{mesh: block.stl, unit: m, count: 0}]\n", "parts[0].count", "must be between 1 and 100000"},
           {"parts: [{mesh: block.stl, unit: yd, count: 1}]\n", "parts[0].unit", "unknown unit 'yd'"},
           {"parts: [{mesh: block.stl, count: 1}]\n", "parts[0].unit", "required: the unit"},
           {"parts: [{mesh_id: m, unit: mm, count: 1}]\n", "parts[0].unit", "in metres already"},
           {"parts: [{count: 1}]\n", "parts[0]", "give either mesh"},
           {"parts: [{mesh: block.stl, unit: m, count: 1, scale: -1}]\n", "parts[0].scale", "must be positive"},
           {"parts: [{mesh: block.stl, unit: m, count: 1, mass_kg: .nan}]\n", "parts[0].mass_kg", "not finite"},
           {"parts: [{mesh: block.stl, unit: m, count: 1, collision: sphere}]\n", "parts[0].collision",
            "unknown collision shape"},
           {"parts: []\n", "parts", "at least 1"},
       }) {
    const Status from_cli = AsBinPlan(bin + parts).status();
    const Status from_dataset = AsDataset(bin + parts).status();
    EXPECT_EQ(from_cli.code(), StatusCode::kInvalidArgument) << parts;
    EXPECT_EQ(from_dataset.code(), StatusCode::kInvalidArgument) << parts;
    EXPECT_TRUE(from_cli.message().starts_with("p.yaml:3: " + key + ": ")) << from_cli.message();
    EXPECT_TRUE(from_dataset.message().starts_with("p.yaml:4: bins[0]." + key + ": ")) << from_dataset.message();
    EXPECT_NE(from_cli.message().find(what), std::string::npos) << from_cli.message();
    EXPECT_EQ(from_cli.message().substr(from_cli.message().find(key)),
              from_dataset.message().substr(from_dataset.message().find(key)));
  }
}

// A part's material travels to the bin fill's spec and to the dataset's part; a choice among
// several is a dataset's alone.
TEST_F(BinFillPlanTest, APartsMaterialReachesTheSpecAndTheDatasetsPart) {
  const std::string fill =
      "bin: {inner_size: [0.3, 0.2, 0.1]}\n"
      "parts:\n"
      "  - {mesh_id: m-1, count: 1, material: polished-steel}\n"
      "  - {mesh_id: m-2, count: 1, material: {diffuse_albedo: 0.2, metallic: 1, roughness: 0.3, "
      "specular_reflectance: 0.04}}\n";
  const StatusOr<cli::BinPlan> bin = AsBinPlan(fill);
  ASSERT_TRUE(bin.ok()) << bin.status().ToString();
  EXPECT_EQ(bin->spec.parts(0).material().preset(), "polished-steel");
  EXPECT_FALSE(bin->spec.parts(0).material().has_values());
  EXPECT_EQ(bin->spec.parts(1).material().values().roughness(), 0.3);
  EXPECT_EQ(bin->spec.parts(1).material().values().metallic(), 1.0);
  const Status refused = AsBinPlan(
      "bin: {inner_size: [0.3, 0.2, 0.1]}\nparts: [{mesh_id: m, count: 1, material: {diffuse_albedo: 0.2}}]\n")
                             .status();
  EXPECT_NE(refused.message().find("parts[0].material.metallic: required"), std::string::npos) << refused.message();
  const StatusOr<service::dataset::DatasetPlan> dataset = AsDataset(fill);
  ASSERT_TRUE(dataset.ok()) << dataset.status().ToString();
  EXPECT_EQ(dataset->bin_fills[0].parts[0].materials.at(0).preset, "polished-steel");
  EXPECT_EQ(dataset->bin_fills[0].parts[1].materials.at(0).roughness, 0.3);
  const std::string choice = "bin: {inner_size: [0.3, 0.2, 0.1]}\nparts:\n"
                             "  - {mesh_id: m-1, count: 1, material: {choose: [white-abs, black-abs]}}\n";
  EXPECT_EQ(AsBinPlan(choice).status().message(),
            "p.yaml:4: parts[0].material: a bin fill takes one material; choose is for dataset plans");
  ASSERT_TRUE(AsDataset(choice).ok()) << AsDataset(choice).status().ToString();
}

// The picks block becomes spec.picks field by field; the server's refusal of one of its fields
// points back at the plan's line.
TEST_F(BinFillPlanTest, APicksBlockReachesTheSpecAndItsRefusalsPointAtTheLine) {
  const std::string fill =
      "bin: {inner_size: [0.3, 0.2, 0.1]}\n"
      "parts: [{mesh_id: m, count: 2}]\n"
      "picks:\n"
      "  mount_id: mnt_1\n"
      "  gripper: {suction: {diameter: 0.012}}\n"
      "  grasp_options: {max_grasps: 200}\n"
      "  pick_options: {body_length: 0.08, max_approach_tilt_deg: 45}\n";
  const StatusOr<cli::BinPlan> plan = AsBinPlan(fill);
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const v1::BinPicks& picks = plan->spec.picks();
  EXPECT_EQ(picks.mount_id(), "mnt_1");
  EXPECT_EQ(picks.gripper().suction().diameter(), 0.012);
  EXPECT_EQ(picks.grasp_options().max_grasps(), 200u);
  EXPECT_EQ(picks.pick_options().body_length(), 0.08);
  EXPECT_EQ(picks.pick_options().max_approach_tilt_deg(), 45);
  const auto located =
      cli::LocateInBinPlan(*plan, InvalidArgument("spec.picks.gripper.suction.diameter_m: must be a length"));
  ASSERT_TRUE(located.has_value());
  EXPECT_TRUE(located->starts_with("p.yaml:6: picks.gripper.suction.diameter_m: ")) << *located;
  const Status unknown = AsBinPlan(fill + "  reach: 1\n").status();
  EXPECT_EQ(unknown.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.message().find("p.yaml:9"), std::string::npos) << unknown.message();
  EXPECT_FALSE(AsBinPlan("bin: {inner_size: [0.3, 0.2, 0.1]}\nparts: [{mesh_id: m, count: 2}]\n")->spec.has_picks());
}

TEST(UnitNames, ShortAndLongNamesAndTheirLengths) {
  EXPECT_EQ(plan::ShortUnitName("Millimetre"), "mm");
  EXPECT_EQ(plan::ShortUnitName("feet"), "ft");
  EXPECT_EQ(plan::ShortUnitName("yd"), std::nullopt);
  EXPECT_EQ(plan::MetresPerUnit("in"), 0.0254);
  EXPECT_EQ(plan::MetresPerUnit("inch"), std::nullopt);  // short names only: ShortUnitName first
}

}  // namespace
}  // namespace vscan
