// Scene numbering, shards by seed, and the plan file.

#include <gtest/gtest.h>

#include <set>

#include "service/datasets/format/dataset_manifest.h"
#include "service/datasets/format/dataset_plan.h"
#include "service/datasets/format/dataset_plan_yaml.h"

namespace vscan::service::dataset {
namespace {

DatasetPlan ThreeByTwoByTwo() {
  DatasetPlan plan;
  plan.bins = {"small", "large"};
  plan.seeds = {40, 41, 42};
  plan.sensors = {"near", "far"};
  return plan;
}

TEST(DatasetPlan, ScenesRunSeedThenBinThenSensor) {
  const DatasetPlan plan = ThreeByTwoByTwo();
  ASSERT_TRUE(CheckPlan(plan).ok());
  ASSERT_EQ(SceneCount(plan), 12u);
  uint64_t id = 0;
  for (size_t seed = 0; seed < 3; ++seed) {
    for (size_t bin = 0; bin < 2; ++bin) {
      for (size_t sensor = 0; sensor < 2; ++sensor, ++id) {
        const SceneKey key = SceneAt(plan, id);
        EXPECT_EQ(key.scene_id, id);
        EXPECT_EQ(key.seed_index, seed);
        EXPECT_EQ(key.seed, plan.seeds[seed]);
        EXPECT_EQ(key.bin_index, bin);
        EXPECT_EQ(key.sensor_index, sensor);
      }
    }
  }
}

TEST(DatasetPlan, ShardsSplitTheScenesBySeed) {
  const DatasetPlan plan = ThreeByTwoByTwo();
  for (uint32_t shards = 1; shards <= 5; ++shards) {
    std::multiset<uint64_t> all;
    for (uint32_t shard = 0; shard < shards; ++shard) {
      std::set<size_t> seeds_here;
      for (const uint64_t id : ScenesOfShard(plan, shard, shards)) {
        EXPECT_EQ(ShardOfScene(plan, id, shards), shard);
        seeds_here.insert(SceneAt(plan, id).seed_index);
        all.insert(id);
      }
      // A seed on this shard brings every bin and sensor with it.
      EXPECT_EQ(ScenesOfShard(plan, shard, shards).size(), seeds_here.size() * 4);
    }
    ASSERT_EQ(all.size(), SceneCount(plan)) << shards << " shards";
    EXPECT_EQ(std::set<uint64_t>(all.begin(), all.end()).size(), SceneCount(plan)) << "a scene on two shards";
  }
  EXPECT_EQ(ScenesOfShard(plan, 1, 2), (std::vector<uint64_t>{4, 5, 6, 7}));
  EXPECT_TRUE(ScenesOfShard(plan, 4, 5).empty());
}

TEST(DatasetPlan, RefusesRepeatsEmptiesAndBadShards) {
  DatasetPlan plan = ThreeByTwoByTwo();
  plan.seeds = {1, 2, 1};
  EXPECT_EQ(CheckPlan(plan).field(), "seeds[2]");
  plan = ThreeByTwoByTwo();
  plan.sensors = {"a", "a"};
  EXPECT_EQ(CheckPlan(plan).field(), "sensors[1]");
  plan = ThreeByTwoByTwo();
  plan.bins = {"with/slash"};
  EXPECT_EQ(CheckPlan(plan).field(), "bins[0]");
  plan = ThreeByTwoByTwo();
  plan.bins.clear();
  EXPECT_EQ(CheckPlan(plan).field(), "bins");
  plan = ThreeByTwoByTwo();
  plan.depth_scale_mm = 0;
  EXPECT_EQ(CheckPlan(plan).field(), "depth_scale_mm");
  plan.depth_scale_mm = 1e-20;  // the floor 0.6 m down would not fit 16 bits
  EXPECT_EQ(CheckPlan(plan).field(), "depth_scale_mm");
  plan = ThreeByTwoByTwo();
  plan.seeds = SeedRange(0, kMaxScenes / 2);
  EXPECT_EQ(CheckPlan(plan).field(), "seeds");
  EXPECT_FALSE(CheckShard(0, 0).ok());
  EXPECT_FALSE(CheckShard(3, 3).ok());
  EXPECT_TRUE(CheckShard(2, 3).ok());
}

TEST(DatasetPlanYaml, ReadsARangeOfSeeds) {
  StatusOr<DatasetPlan> plan = ParseDatasetPlanYaml(
      "name: demo\nbins: [small, large]\nseeds: {first: 100, count: 3}\nsensors: [near]\ndepth_scale_mm: 0.05\n",
      "plan.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->name, "demo");
  EXPECT_EQ(plan->bins, (std::vector<std::string>{"small", "large"}));
  EXPECT_EQ(plan->seeds, (std::vector<uint64_t>{100, 101, 102}));
  EXPECT_EQ(plan->sensors, (std::vector<std::string>{"near"}));
  EXPECT_DOUBLE_EQ(plan->depth_scale_mm, 0.05);
}

TEST(DatasetPlanYaml, ReadsAListOfSeedsAndDefaultsTheScale) {
  StatusOr<DatasetPlan> plan = ParseDatasetPlanYaml("bins: [b]\nseeds: [9, 3, 5]\nsensors: [s]\n", "plan.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->seeds, (std::vector<uint64_t>{9, 3, 5}));
  EXPECT_DOUBLE_EQ(plan->depth_scale_mm, 0.1);
}

TEST(DatasetPlanYaml, FailOnUnderfilledBinIsOffUnlessSetAndMustBeABoolean) {
  const std::string base = "bins: [b]\nseeds: [1]\nsensors: [s]\n";
  StatusOr<DatasetPlan> plan = ParseDatasetPlanYaml(base, "p.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_FALSE(plan->fail_on_underfilled_bin);
  plan = ParseDatasetPlanYaml(base + "fail_on_underfilled_bin: true\n", "p.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_TRUE(plan->fail_on_underfilled_bin);
  const Status refused = ParseDatasetPlanYaml(base + "fail_on_underfilled_bin: sometimes\n", "p.yaml").status();
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(refused.message(), "p.yaml: fail_on_underfilled_bin: must be true or false");
}

TEST(DatasetPlanYaml, NamesTheKeyItRefuses) {
  const auto message = [](const std::string& text) {
    return ParseDatasetPlanYaml(text, "p.yaml").status().message();
  };
  EXPECT_EQ(message("bins: [b]\nseeds: [1]\nsensors: [s]\ncolour: red\n"),
            "p.yaml: colour: is not a key (name, bins, seeds, sensors, depth_scale_mm, camera_height_m, views, "
            "fail_on_underfilled_bin, returned_light, picks)");
  EXPECT_EQ(message("bins: [b]\nsensors: [s]\n"), "p.yaml: seeds: is missing");
  EXPECT_EQ(message("bins: [b]\nseeds: {first: 1}\nsensors: [s]\n"), "p.yaml: seeds: needs both first and count");
  EXPECT_EQ(message("bins: [b]\nseeds: [1, -2]\nsensors: [s]\n"),
            "p.yaml: seeds[1]: must be a non-negative whole number");
  EXPECT_EQ(message("bins: [b, b]\nseeds: [1]\nsensors: [s]\n"), "p.yaml: bins[1]: 'b' appears twice");
  EXPECT_EQ(ParseDatasetPlanYaml("bins: [", "p.yaml").status().code(), StatusCode::kInvalidArgument);
}

TEST(DatasetPlanYaml, ReadsBinFillsAndSensorSetups) {
  StatusOr<DatasetPlan> plan = ParseDatasetPlanYaml(
      "bins:\n"
      "  - name: mixed\n"
      "    bin: {inner_size: [0.3, 0.2, 0.1], wall_thickness: 0.02}\n"
      "    parts:\n"
      "      - {mesh: parts/block.stl, unit: in, count: 3}\n"
      "      - {mesh_id: m-1, count: 2, scale: 0.5, name: rod}\n"
      "seeds: [4]\n"
      "sensors: [kinect-v2-class, {name: small, preset: ideal-vga, width: 160, height: 120}]\n"
      "camera_height_m: 0.8\n",
      "plan.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->bins, (std::vector<std::string>{"mixed"}));
  ASSERT_EQ(plan->bin_fills.size(), 1u);
  const DatasetBinFill& fill = plan->bin_fills[0];
  EXPECT_EQ(fill.inner_size_m, Eigen::Vector3d(0.3, 0.2, 0.1));
  EXPECT_EQ(fill.wall_thickness_m, 0.02);
  ASSERT_EQ(fill.parts.size(), 2u);
  EXPECT_EQ(fill.parts[0].mesh_file, "parts/block.stl");
  EXPECT_EQ(fill.parts[0].unit, "in");
  EXPECT_EQ(fill.parts[0].name, "block");
  EXPECT_EQ(fill.parts[1].mesh_id, "m-1");
  EXPECT_EQ(fill.parts[1].scale, 0.5);
  EXPECT_EQ(plan->sensors, (std::vector<std::string>{"kinect-v2-class", "small"}));
  ASSERT_EQ(plan->sensor_setups.size(), 2u);
  EXPECT_EQ(plan->sensor_setups[0].preset, "kinect-v2-class");
  EXPECT_EQ(plan->sensor_setups[1].preset, "ideal-vga");
  EXPECT_EQ(plan->sensor_setups[1].width, 160u);
  EXPECT_EQ(plan->camera_height_m, 0.8);
}

// A part's mass, density and collision make a different dataset; a plan without them keeps the
// manifest (the dataset's identity) that plans had before parts took them.
TEST(DatasetPlanYaml, APartsPhysicsIsPartOfTheDatasetsIdentity) {
  const auto manifest = [](const std::string& part) {
    const auto plan = ParseDatasetPlanYaml("bins:\n  - name: b\n    bin: {inner_size: [0.3, 0.2, 0.1]}\n"
                                           "    parts: [{mesh: block.stl, unit: m, count: 3" + part + "}]\n"
                                           "seeds: [4]\nsensors: [ideal-vga]\ncamera_height_m: 0.8\n",
                                           "plan.yaml");
    EXPECT_TRUE(plan.ok()) << plan.status().ToString();
    return plan.ok() ? DatasetManifestJson(*plan) : std::string();
  };
  const std::string plain = manifest("");
  EXPECT_EQ(plain.find("collision"), std::string::npos);
  EXPECT_EQ(plain.find("mass_kg"), std::string::npos);
  EXPECT_EQ(plain.find("density_kg_per_m3"), std::string::npos);
  EXPECT_EQ(manifest(", collision: convex_hull, density_kg_per_m3: 2700"), plain);
  std::set<std::string> distinct = {plain};
  for (const std::string part : {", collision: convex_decomposition", ", mass_kg: 0.2", ", density_kg_per_m3: 7800",
                                 ", material: white-abs", ", material: {choose: [white-abs, black-abs]}",
                                 ", material: {choose: [black-abs, white-abs]}"}) {
    EXPECT_TRUE(distinct.insert(manifest(part)).second) << part;
  }
  EXPECT_EQ(plain.find("material"), std::string::npos);
  EXPECT_EQ(plain.find("returned_light"), std::string::npos);
}

// A lit plan and an unlit one, or two lights, are two datasets.
TEST(DatasetPlanYaml, TheReturnedLightIsPartOfTheDatasetsIdentity) {
  const auto manifest = [](const std::string& light) {
    const auto plan = ParseDatasetPlanYaml("bins:\n  - name: b\n    bin: {inner_size: [0.3, 0.2, 0.1]}\n"
                                           "    parts: [{mesh: block.stl, unit: m, count: 3}]\n"
                                           "seeds: [4]\nsensors: [ideal-vga]\n" + light,
                                           "plan.yaml");
    EXPECT_TRUE(plan.ok()) << plan.status().ToString();
    return plan.ok() ? DatasetManifestJson(*plan) : std::string();
  };
  const std::set<std::string> distinct = {manifest(""), manifest("returned_light: {}\n"),
                                          manifest("returned_light: {emitter_w_per_sr: 0.5}\n"),
                                          manifest("returned_light: {min_snr: 3}\n")};
  EXPECT_EQ(distinct.size(), 4u);
  EXPECT_NE(manifest("returned_light: {min_snr: 3}\n").find("\"min_snr\":3"), std::string::npos);
}

// A dataset's bins are read by the bin plans' reader (vscan/plan/bin_fill_plan.h): its messages,
// with the line, and the dataset's own limits on top.
TEST(DatasetPlanYaml, NamesTheBinKeyItRefuses) {
  const auto message = [](const std::string& bins) {
    return ParseDatasetPlanYaml("bins:\n" + bins + "seeds: [1]\nsensors: [s]\n", "p.yaml").status().message();
  };
  const std::string box = "    bin: {inner_size: [0.3, 0.2, 0.1]}\n";
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh: a.stl, unit: m, count: 0}]\n"),
            "p.yaml:4: bins[0].parts[0].count: must be between 1 and 100000");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh: a.stl, count: 1}]\n"),
            "p.yaml:4: bins[0].parts[0].unit: required: the unit the mesh is written in (m, cm, mm, in, ft)");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh: a.stl, unit: yd, count: 1}]\n"),
            "p.yaml:4: bins[0].parts[0].unit: unknown unit 'yd' (m, cm, mm, in, ft)");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{count: 1}]\n"),
            "p.yaml:4: bins[0].parts[0]: give either mesh (a file) or mesh_id (an uploaded mesh)");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh_id: m-1, unit: mm, count: 1}]\n"),
            "p.yaml:4: bins[0].parts[0].unit: an uploaded mesh is in metres already; use scale");
  EXPECT_EQ(message("  - name: a\n    bin: {inner_size: [0.3, 0.2, 0]}\n    parts: [{mesh: a.stl, unit: m, count: 1}]\n"),
            "p.yaml: bins[0].bin.inner_size: each size must be within [0.001, 100] m");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh: a.stl, unit: m, count: 1}]\n  - b\n"),
            "p.yaml: bins[1]: describe every bin's fill or none");
  EXPECT_EQ(message("  - name: a\n" + box + "    parts: [{mesh: a.stl, unit: m, count: 1, colour: red}]\n"),
            "p.yaml:4: bins[0].parts[0].colour: unknown key (expected one of mesh, mesh_id, unit, count, scale, "
            "name, mass_kg, density_kg_per_m3, collision, material)");
  EXPECT_EQ(message("  - name: a\n    bin: {mesh: tote.stl, unit: mm}\n    parts: [{mesh: a.stl, unit: m, count: 1}]\n"),
            "p.yaml:3: bins[0].bin: a dataset's bins are boxes (inner_size, wall_thickness)");
  EXPECT_EQ(message("  - name: a\n    bin: {inner_size: [0.3, 0.2, 0.1], pose: {xyz: [1, 0, 0]}}\n"
                    "    parts: [{mesh: a.stl, unit: m, count: 1}]\n"),
            "p.yaml:3: bins[0].bin.pose: a dataset's bin stands at the origin");
  // The spelling plans had before bin plans and datasets shared a reader is refused with the new one.
  EXPECT_EQ(message("  - name: a\n    box: {inner_size_m: [0.3, 0.2, 0.1]}\n    parts: [{mesh: a.stl, unit: m, count: 1}]\n"),
            "p.yaml: bins[0].box: is now written as bin plans write it: bin: {inner_size: [x, y, z], "
            "wall_thickness: w} (docs/DATASETS.md)");
}

TEST(DatasetPlanYaml, ReadsViewsAndDefaultsToOneStraightDown) {
  const std::string base = "bins: [b]\nseeds: [1]\nsensors: [s]\n";
  StatusOr<DatasetPlan> plan = ParseDatasetPlanYaml(base, "p.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->views, DatasetViews{});
  EXPECT_EQ(ViewDistanceRange(*plan), (std::pair<double, double>{0.6, 0.6}));
  plan = ParseDatasetPlanYaml(base + "views: {count: 12, cone_deg: 30, distance_m: [0.5, 0.9]}\n", "p.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(plan->views, (DatasetViews{12, 30.0, 0.5, 0.9}));
  EXPECT_EQ(ViewDistanceRange(*plan), (std::pair<double, double>{0.5, 0.9}));
  plan = ParseDatasetPlanYaml(base + "views: {count: 2, distance_m: 0.7}\n", "p.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  EXPECT_EQ(ViewDistanceRange(*plan), (std::pair<double, double>{0.7, 0.7}));
}

TEST(DatasetPlanYaml, RefusesViewsOutsideTheirBoundsNamingTheKey) {
  const auto message = [](const std::string& views) {
    return ParseDatasetPlanYaml("bins: [b]\nseeds: [1]\nsensors: [s]\nviews: " + views + "\n", "p.yaml")
        .status()
        .message();
  };
  EXPECT_EQ(message("{count: 0}"), "p.yaml: views.count: must be within [1, 1000]");
  EXPECT_EQ(message("{count: 1001}"), "p.yaml: views.count: must be within [1, 1000]");
  EXPECT_EQ(message("{count: -3}"), "p.yaml: views.count: must be a non-negative whole number");
  EXPECT_EQ(message("{cone_deg: 85}"), "p.yaml: views.cone_deg: must be within [0, 80] degrees of straight down");
  EXPECT_EQ(message("{cone_deg: .nan}"), "p.yaml: views.cone_deg: must be within [0, 80] degrees of straight down");
  EXPECT_EQ(message("{distance_m: [0.9, 0.5]}"), "p.yaml: views.distance_m: must be [min, max] with 0 < min <= max <= 100 m");
  EXPECT_EQ(message("{distance_m: [0.5, 1e19]}"), "p.yaml: views.distance_m: must be [min, max] with 0 < min <= max <= 100 m");
  EXPECT_EQ(message("{distance_m: [0, 0]}"), "p.yaml: views.distance_m: must be positive");
  EXPECT_EQ(message("{distance_m: [0.5, 0.6, 0.7]}"), "p.yaml: views.distance_m: must be one distance or [min, max]");
  EXPECT_EQ(message("{tilt: 3}"), "p.yaml: views.tilt: is not a key (count, cone_deg, distance_m)");
  EXPECT_EQ(message("[3]"), "p.yaml: views: must be a mapping (count, cone_deg, distance_m)");
}

TEST(DatasetPlanYaml, DeeplyNestedTextIsRefusedBeforeParsingNamingTheLine) {
  const std::string base = "bins: [b]\nseeds: [1]\nsensors: [s]\n";
  const Status flow = ParseDatasetPlanYaml(base + "name: " + std::string(100000, '[') + "\n", "p.yaml").status();
  EXPECT_EQ(flow.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(flow.message(), "p.yaml: line 4: more than 64 nested lists or mappings: nested too deep for a plan");
  std::string block = base + "name:\n";
  for (int i = 1; i < 300; ++i) block += std::string(i, ' ') + "- \n";
  const Status indented = ParseDatasetPlanYaml(block, "p.yaml").status();
  EXPECT_EQ(indented.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(indented.message().find("indented more than 256 columns"), std::string::npos) << indented.message();
  // Brackets inside quotes and comments are text, and 64 levels still parse as YAML.
  EXPECT_TRUE(ParseDatasetPlanYaml(base + "name: '" + std::string(200, '[') + "' # " + std::string(200, '{') + "\n",
                                   "p.yaml").ok());
  const Status deep = ParseDatasetPlanYaml(base + "depth_scale_mm: " + std::string(64, '[') + std::string(64, ']') + "\n",
                                           "p.yaml").status();
  EXPECT_EQ(deep.message(), "p.yaml: depth_scale_mm: must be a number");
}

TEST(DatasetPlan, BoundsImagesNotScenes) {
  DatasetPlan plan;
  plan.bins = {"b"};
  plan.sensors = {"s"};
  plan.seeds = SeedRange(0, 2000);
  plan.views.count = 500;
  EXPECT_TRUE(CheckPlan(plan).ok());
  plan.views.count = 501;
  const Status refused = CheckPlan(plan);
  EXPECT_EQ(refused.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(refused.field(), "seeds");
  EXPECT_NE(refused.ToString().find("the plan makes 1002000"), std::string::npos) << refused.ToString();
}

TEST(DatasetPlan, TheFarthestViewMustFitTheDepthImage) {
  DatasetPlan plan;
  plan.bins = {"b"};
  plan.sensors = {"s"};
  plan.seeds = {1};
  plan.views = {4, 20.0, 0.5, 7.0};
  const Status refused = CheckPlan(plan);
  EXPECT_EQ(refused.field(), "depth_scale_mm");
  EXPECT_NE(refused.ToString().find("7 m from the camera (views.distance_m)"), std::string::npos) << refused.ToString();
  plan.depth_scale_mm = 0.2;
  EXPECT_TRUE(CheckPlan(plan).ok());
}

}  // namespace
}  // namespace vscan::service::dataset
