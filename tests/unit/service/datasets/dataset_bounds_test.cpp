// The dataset bounds: images and bytes a plan asks for, the scene bound, a directory measured as
// scenes appear, and dataset directories removed and swept only where a job's directory may be.

#include "service/datasets/dataset_bounds.h"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <string>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/dataset_directories.h"
#include "service/datasets/dataset_space.h"
#include "vscan_test/temp_dir.h"

namespace vscan::service {
namespace {

namespace fs = std::filesystem;

dataset::DatasetPlan Plan(size_t seeds, size_t bins, size_t sensors) {
  dataset::DatasetPlan plan;
  for (size_t i = 0; i < seeds; ++i) plan.seeds.push_back(i + 1);
  for (size_t i = 0; i < bins; ++i) plan.bins.push_back("bin" + std::to_string(i));
  for (size_t i = 0; i < sensors; ++i) plan.sensors.push_back("sensor" + std::to_string(i));
  return plan;
}

DatasetSensorSetup Sensor(uint32_t width, uint32_t height) {
  DatasetSensorSetup sensor;
  sensor.camera.width = width;
  sensor.camera.height = height;
  return sensor;
}

void WriteFile(const fs::path& path, size_t bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << std::string(bytes, 'x');
}

TEST(DatasetBoundsTest, ImagesAreScenesTimesViews) {
  dataset::DatasetPlan plan = Plan(7, 3, 2);
  EXPECT_EQ(DatasetViewsPerScene(plan), 1u);
  EXPECT_EQ(DatasetImageCount(plan), 42u);
  plan.views.count = 5;
  EXPECT_EQ(DatasetImageCount(plan), 210u);
}

TEST(DatasetBoundsTest, EstimateCountsEachSensorsPixelsModelsAndTheTar) {
  DatasetSetup setup;
  setup.plan = Plan(5, 2, 2);
  setup.sensors = {Sensor(100, 50), Sensor(20, 10)};
  dataset::PartModel part;
  part.mesh.vertices.resize(8);
  part.mesh.triangles.resize(12);
  setup.parts.push_back(part);
  const DatasetBytes bytes = EstimateDatasetBytes(setup);
  // Each sensor sees 5 seeds x 2 bins; a PLY model is its header, 12 bytes a vertex, 13 a triangle.
  const uint64_t images = 10 * (100 * 50 + 20 * 10) * kDatasetBytesPerPixel;
  EXPECT_EQ(bytes.directory, images + 256 + 8 * 12 + 12 * 13);
  EXPECT_EQ(bytes.tar, bytes.directory);
  EXPECT_EQ(bytes.total(), 2 * bytes.directory);
  // Past the tar's bound the directory is the whole of it.
  setup.sensors = {Sensor(4096, 4096)};
  setup.plan = Plan(1000, 1, 1);
  const DatasetBytes large = EstimateDatasetBytes(setup);
  EXPECT_GT(large.directory, kMaxTarArtifactBytes);
  EXPECT_EQ(large.tar, 0u);
}

// The tar is built in memory: a server that lets one request hold less makes no larger tar.
TEST(DatasetBoundsTest, TheTarIsBoundedByWhatOneRequestMayHold) {
  EXPECT_EQ(DatasetTarBound(0), kMaxTarArtifactBytes);
  EXPECT_EQ(DatasetTarBound(uint64_t{4} << 30), kMaxTarArtifactBytes);
  EXPECT_EQ(DatasetTarBound(uint64_t{256} << 20), uint64_t{256} << 20);
  DatasetSetup setup;
  setup.plan = Plan(5, 2, 2);
  setup.sensors = {Sensor(100, 50)};
  const DatasetBytes fits = EstimateDatasetBytes(setup, DatasetTarBound(uint64_t{256} << 20));
  EXPECT_EQ(fits.tar, fits.directory);
  const DatasetBytes over = EstimateDatasetBytes(setup, fits.directory - 1);
  EXPECT_EQ(over.tar, 0u);
}

TEST(DatasetBoundsTest, ScenesPastTheBoundAreResourceExhaustedNamingSeedsAndTheFlag) {
  EXPECT_TRUE(CheckDatasetScenes(Plan(5, 2, 1), 10).ok());
  const Status over = CheckDatasetScenes(Plan(6, 2, 1), 10);
  ASSERT_EQ(over.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(over.field(), "seeds");
  EXPECT_NE(over.message().find("12 scenes"), std::string::npos) << over.message();
  EXPECT_NE(over.message().find("--max-dataset-scenes"), std::string::npos) << over.message();
}

TEST(DatasetSpaceMeterTest, AddsOnlyFinishedScenesThatAppeared) {
  test::TempDir dir;
  const fs::path root = dir.path() / "ds";
  WriteFile(root / "dataset.json", 100);
  WriteFile(dataset::SceneDir(root, 0) / "cloud" / "000000.ply", 1000);
  WriteFile(dataset::PartialSceneDir(root, 1) / "depth" / "000000.png", 50);
  DatasetSpaceMeter meter(root);
  // The whole tree, the partial scene included.
  ASSERT_EQ(*meter.MeasureAll(), 1150u);
  // Scene 1 finished (its partial renamed) and scene 2 begun: only scene 1 is added, its 50 bytes
  // counted twice until the next whole measure (a run measures all after removing partials).
  fs::rename(dataset::PartialSceneDir(root, 1), dataset::SceneDir(root, 1));
  WriteFile(dataset::PartialSceneDir(root, 2) / "depth" / "000000.png", 70);
  WriteFile(dataset::SceneDir(root, 1) / "cloud" / "000000.ply", 400);
  EXPECT_EQ(*meter.MeasureNewScenes(), 1150u + 450u);
  // Nothing new: the same figure, scene 0 and 1 not walked again.
  EXPECT_EQ(*meter.MeasureNewScenes(), 1600u);
  fs::rename(dataset::PartialSceneDir(root, 2), dataset::SceneDir(root, 2));
  EXPECT_EQ(*meter.MeasureNewScenes(), 1670u);
  WriteFile(root / "scenes.json", 30);
  EXPECT_EQ(*meter.MeasureAll(), 100u + 1000u + 450u + 70u + 30u);
}

TEST(DatasetDirectoriesTest, NamesOfJobsOnly) {
  EXPECT_TRUE(IsDatasetDirectoryName("job_0123456789abcdef"));
  for (const char* name : {"", "job_", "jobs", ".", "..", "job_../x", "job_a/b", "notes", ".removing-job_1"}) {
    EXPECT_FALSE(IsDatasetDirectoryName(name)) << name;
  }
}

TEST(DatasetDirectoriesTest, RemoveCountsAndForgetsTheDirectory) {
  test::TempDir dir;
  auto quota = std::make_shared<store::DataQuota>(10000, std::vector<fs::path>{});
  DatasetDirectories directories(dir.path(), quota);
  WriteFile(directories.Root("job_a") / "train_pbr" / "000000" / "x", 700);
  WriteFile(directories.Root("job_b") / "dataset.json", 300);
  ASSERT_EQ(*directories.Reconcile({"job_a", "job_b"}), 0);
  EXPECT_EQ(quota->used_bytes(), 1000u);
  EXPECT_EQ(directories.Charge("job_b", 500, 9500, "the next scene").code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(quota->used_bytes(), 1200u);
  const StatusOr<uint64_t> removed = directories.Remove("job_a");
  ASSERT_TRUE(removed.ok()) << removed.status().ToString();
  EXPECT_EQ(*removed, 700u);
  EXPECT_FALSE(fs::exists(directories.Root("job_a")));
  EXPECT_FALSE(fs::exists(dir.path() / "datasets" / ".removing-job_a"));
  EXPECT_EQ(quota->used_bytes(), 500u);
  // Nothing there: nothing removed. A name that is not a job's is refused, never resolved.
  EXPECT_EQ(*directories.Remove("job_a"), 0u);
  WriteFile(dir.path() / "keep" / "file", 10);
  EXPECT_FALSE(directories.Remove("../keep").ok());
  EXPECT_FALSE(directories.Remove("..").ok());
  EXPECT_TRUE(fs::exists(dir.path() / "keep" / "file"));
}

TEST(DatasetDirectoriesTest, ReconcileSweepsUnnamedAndHalfRemovedDirectoriesOnly) {
  test::TempDir dir;
  auto quota = std::make_shared<store::DataQuota>(10000, std::vector<fs::path>{});
  DatasetDirectories directories(dir.path(), quota);
  const fs::path datasets = dir.path() / "datasets";
  WriteFile(datasets / "job_named" / "f", 100);
  WriteFile(datasets / "job_orphan" / "f", 200);
  WriteFile(datasets / ".removing-job_gone" / "f", 300);
  WriteFile(datasets / "notes" / "f", 400);
  WriteFile(dir.path() / "outside" / "f", 500);
  fs::create_directory_symlink(dir.path() / "outside", datasets / "job_link");
  ASSERT_EQ(*directories.Reconcile({"job_named", "job_link"}), 2);
  EXPECT_TRUE(fs::exists(datasets / "job_named" / "f"));
  EXPECT_FALSE(fs::exists(datasets / "job_orphan"));
  EXPECT_FALSE(fs::exists(datasets / ".removing-job_gone"));
  EXPECT_TRUE(fs::exists(datasets / "notes" / "f"));
  // A link is neither followed nor removed.
  EXPECT_TRUE(fs::is_symlink(datasets / "job_link"));
  EXPECT_TRUE(fs::exists(dir.path() / "outside" / "f"));
  EXPECT_EQ(quota->used_bytes(), 100u);
}

}  // namespace
}  // namespace vscan::service
