// One set of part checks for every plan that fills a bin: a part refused by a bin fill's request
// (what `vscan bin fill`, Python and StartBinFill send) is refused in the same words, under the
// same field, by a dataset plan's bin, and a part one accepts the other accepts.

#include <gtest/gtest.h>

#include <string>

#include "service/bins/bin_fill_plan.h"
#include "service/datasets/dataset_job_setup.h"
#include "service/datasets/format/dataset_plan_yaml.h"
#include "service_world.h"
#include "vscan_test/meshes.h"

namespace vscan::service {
namespace {

// A bin fill of one part type (mesh, scale, optional mass) into a 30 x 20 x 15 cm box.
Status BinFillVerdict(testing::ServiceWorld& world, const TriangleMesh& mesh, double scale, const char* mass_kg) {
  BinFillRequest request;
  request.scene_id = world.EmptyScene();
  request.bin.inner_size = Eigen::Vector3d(0.30, 0.20, 0.15);
  BinPartRequest part;
  part.mesh_id = world.AddMesh(mesh, "part");
  part.count = 2;
  part.scale = scale;
  if (mass_kg) part.mass_kg = std::stod(mass_kg);
  request.parts.push_back(part);
  return PlanBinFill(world.context().registry, request).status();
}

// The same part in a dataset plan's bin (the mesh file read by a loader that returns mesh); the
// field loses its "bins[0]." prefix so that both name the part alike.
Status DatasetVerdict(const TriangleMesh& mesh, double scale, const char* mass_kg) {
  std::string yaml = "name: checks\nbins:\n  - name: box\n    bin: {inner_size: [0.30, 0.20, 0.15]}\n"
                     "    parts:\n      - {mesh: part.obj, unit: m, count: 2, scale: " + std::to_string(scale);
  if (mass_kg) yaml += std::string(", mass_kg: ") + mass_kg;
  yaml += "}\nseeds: [1]\nsensors: [ideal-vga]\ncamera_height_m: 0.6\n";
  auto plan = dataset::ParseDatasetPlanYaml(yaml, "checks.yaml");
  if (!plan.ok()) return plan.status();
  const DatasetMeshLoader load = [&](const dataset::DatasetPart&, const std::string&) -> StatusOr<TriangleMesh> {
    return mesh;
  };
  const Status status = PrepareDataset(*plan, load, 1u << 22).status();
  const std::string prefix = "bins[0].";
  if (status.ok() || !status.field().starts_with(prefix)) return status;
  return Status(status.code(), status.field().substr(prefix.size()), std::string(status.text()));
}

const TriangleMesh kCube = test::MakeBox(Eigen::Vector3d::Constant(-0.02), Eigen::Vector3d::Constant(0.02));
const TriangleMesh kSheet = test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.02);

TEST(PartChecks, APartScaledPastTenMetresIsRefusedAlikeByBothPlans) {
  testing::ServiceWorld world;
  const Status bin = BinFillVerdict(world, kCube, 1000, nullptr);
  const Status dataset = DatasetVerdict(kCube, 1000, nullptr);
  ASSERT_EQ(bin.code(), StatusCode::kInvalidArgument) << bin.ToString();
  EXPECT_EQ(bin.field(), "parts[0].scale");
  EXPECT_NE(std::string(bin.text()).find("40.000000 m across"), std::string::npos) << bin.ToString();
  EXPECT_EQ(dataset.code(), bin.code());
  EXPECT_EQ(dataset.field(), bin.field());
  EXPECT_EQ(dataset.text(), bin.text());
}

TEST(PartChecks, APartScaledUnderAMillimetreIsRefusedAlikeByBothPlans) {
  testing::ServiceWorld world;
  const Status bin = BinFillVerdict(world, kCube, 0.01, nullptr);
  const Status dataset = DatasetVerdict(kCube, 0.01, nullptr);
  ASSERT_EQ(bin.code(), StatusCode::kInvalidArgument) << bin.ToString();
  EXPECT_EQ(bin.field(), "parts[0].scale");
  EXPECT_EQ(dataset.field(), bin.field());
  EXPECT_EQ(dataset.text(), bin.text());
}

TEST(PartChecks, AMeshThatEnclosesNoVolumeNeedsAMassInBothPlans) {
  testing::ServiceWorld world;
  const Status bin = BinFillVerdict(world, kSheet, 1, nullptr);
  const Status dataset = DatasetVerdict(kSheet, 1, nullptr);
  ASSERT_EQ(bin.code(), StatusCode::kInvalidArgument) << bin.ToString();
  EXPECT_EQ(bin.field(), "parts[0].mass_kg");
  EXPECT_EQ(dataset.field(), bin.field());
  EXPECT_EQ(dataset.text(), bin.text());
  // With a mass of its own the same sheet is a part in both.
  EXPECT_TRUE(BinFillVerdict(world, kSheet, 1, "0.05").ok());
  EXPECT_TRUE(DatasetVerdict(kSheet, 1, "0.05").ok()) << DatasetVerdict(kSheet, 1, "0.05").ToString();
}

TEST(PartChecks, APartBothAcceptIsAcceptedByBoth) {
  testing::ServiceWorld world;
  EXPECT_TRUE(BinFillVerdict(world, kCube, 1, nullptr).ok());
  EXPECT_TRUE(DatasetVerdict(kCube, 1, nullptr).ok()) << DatasetVerdict(kCube, 1, nullptr).ToString();
}

TEST(PartChecks, ADatasetPartTakesABinPlansMassDensityAndCollision) {
  const std::string yaml =
      "name: checks\nbins:\n  - name: box\n    bin: {inner_size: [0.30, 0.20, 0.15]}\n    parts:\n"
      "      - {mesh: part.obj, unit: m, count: 2, density_kg_per_m3: 1200, collision: convex_decomposition}\n"
      "seeds: [1]\nsensors: [ideal-vga]\ncamera_height_m: 0.6\n";
  auto plan = dataset::ParseDatasetPlanYaml(yaml, "checks.yaml");
  ASSERT_TRUE(plan.ok()) << plan.status().ToString();
  const DatasetMeshLoader load = [](const dataset::DatasetPart&, const std::string&) -> StatusOr<TriangleMesh> {
    return kCube;
  };
  auto setup = PrepareDataset(*plan, load, 1u << 22);
  ASSERT_TRUE(setup.ok()) << setup.status().ToString();
  const physics::PartType& part = setup->bins[0].parts[0];
  EXPECT_DOUBLE_EQ(part.density_kg_per_m3, 1200);
  EXPECT_FALSE(part.mass_kg.has_value());
  EXPECT_EQ(part.collision, physics::PartCollision::kConvexDecomposition);

  const std::string unknown = "collision: convex_decomposition";
  std::string bad = yaml;
  bad.replace(bad.find(unknown), unknown.size(), "collision: spheres");
  const auto refused = dataset::ParseDatasetPlanYaml(bad, "checks.yaml");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(refused.status().message().find("bins[0].parts[0].collision: unknown collision shape 'spheres'"),
            std::string::npos)
      << refused.status().ToString();
}

}  // namespace
}  // namespace vscan::service
