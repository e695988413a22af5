// A results file scored against a small hand-written dataset (a cube of 100 mm, diameter
// 100 sqrt(3) mm): the pooling over images and scenes, the top-n cut per image and object, invalid
// true instances, images the dataset does not have, refusals, and grasp success with a suction cup.

#include "service/datasets/dataset_scoring.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <string>

#include "vscan_test/temp_dir.h"

namespace vscan::service {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string Gt(double x) {
  return R"({"obj_id": 1, "instance_id": 2, "cam_R_m2c": [1, 0, 0, 0, 1, 0, 0, 0, 1], "cam_t_m2c": [)" +
         std::to_string(x) + ", 0, 500]}";
}

// Scene 0: image 0 holds a (x 0), b (x 200) and c (x -200, 5% visible), image 1 holds d (x 0);
// scene 1: image 0 holds e (x 0).
void WriteDataset(const fs::path& root) {
  Write(root / "dataset.json", R"({"format": "vscan-dataset", "scene_count": 2})");
  Write(root / "scenes.json", R"({"scene_count": 2})");
  Write(root / "models/models_info.json", R"({"1": {"diameter": 173.20508075688772}})");
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (int i = 0; i < 8; ++i) {
    ply += std::to_string(i & 1 ? 50 : -50) + " " + std::to_string(i & 2 ? 50 : -50) + " " +
           std::to_string(i & 4 ? 50 : -50) + "\n";
  }
  Write(root / "models/obj_000001.ply", ply);
  Write(root / "train_pbr/000000/scene_gt.json",
        R"({"0": [)" + Gt(0) + ", " + Gt(200) + ", " + Gt(-200) + R"(], "1": [)" + Gt(0) + "]}");
  Write(root / "train_pbr/000000/scene_gt_info.json",
        R"({"0": [{"visib_fract": 0.9}, {"visib_fract": 0.1}, {"visib_fract": 0.05}], "1": [{"visib_fract": 1}]})");
  Write(root / "train_pbr/000001/scene_gt.json", R"({"0": [)" + Gt(0) + "]}");
  Write(root / "train_pbr/000001/scene_gt_info.json", R"({"0": [{"visib_fract": 0.5}]})");
}

std::string Row(int scene, int im, int obj, double score, double x) {
  return std::to_string(scene) + "," + std::to_string(im) + "," + std::to_string(obj) + "," + std::to_string(score) +
         ",1 0 0 0 1 0 0 0 1," + std::to_string(x) + " 0 500,-1\n";
}

StatusOr<DatasetScore> Score(const fs::path& root, const std::string& csv, const DatasetScoringOptions& options = {}) {
  auto rows = dataset::ParseBopResultsCsv(csv, "results_csv");
  if (!rows.ok()) return rows.status();
  return ScoreDatasetResults(root, *rows, options, "results_csv");
}

// On c (invalid, best scored), on a exactly, on b 30 mm off: cut to the two best, b's is dropped.
// d 10 mm off; e none. Two rows for images the dataset lacks.
const std::string kResults = Row(0, 0, 1, 0.95, -200) + Row(0, 0, 1, 0.9, 0) + Row(0, 0, 1, 0.8, 230) +
                             Row(0, 1, 1, 0.5, 10) + Row(5, 0, 1, 1, 0) + Row(0, 7, 1, 1, 0);

TEST(DatasetScoring, PoolsImagesAsBopDoes) {
  test::TempDir dir;
  WriteDataset(dir.path());
  const auto score = Score(dir.path(), kResults);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  EXPECT_EQ(score->scene_count, 2u);
  EXPECT_EQ(score->images, 3u);
  EXPECT_EQ(score->true_instances, 5u);
  EXPECT_EQ(score->rows, 6u);
  EXPECT_EQ(score->ignored_rows, 2u);
  ASSERT_EQ(score->ignored_images.size(), 2u);
  EXPECT_EQ(score->ignored_images[0], std::pair(0u, 7u));
  EXPECT_EQ(score->ignored_images[1], std::pair(5u, 0u));

  // Valid: a, b, d, e. ADD(-S) at 17.3 mm: a (0 mm) and d (10 mm). MSSD: a at every threshold,
  // d (10 mm = 0.058 diameters) from 0.1 on; b's estimate was cut, e has none.
  const RecallCounts& all = score->tally.overall();
  EXPECT_EQ(all.valid_instances, 4u);
  EXPECT_EQ(all.estimates, 4u);
  EXPECT_EQ(all.add_correct, 2u);
  EXPECT_DOUBLE_EQ(*all.AddRecall(), 0.5);
  EXPECT_EQ(all.mssd_correct, (std::vector<uint64_t>{1, 2, 2, 2, 2, 2, 2, 2, 2, 2}));
  EXPECT_DOUBLE_EQ(*all.MssdAverageRecall(), 19.0 / 40.0);

  const RecallCounts& scene0 = score->tally.scenes().at(0);
  EXPECT_EQ(scene0.valid_instances, 3u);
  EXPECT_EQ(scene0.estimates, 4u);
  EXPECT_DOUBLE_EQ(*scene0.AddRecall(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(*scene0.MssdAverageRecall(), 19.0 / 30.0);
  const RecallCounts& scene1 = score->tally.scenes().at(1);
  EXPECT_EQ(scene1.valid_instances, 1u);
  EXPECT_EQ(scene1.estimates, 0u);
  EXPECT_DOUBLE_EQ(*scene1.AddRecall(), 0.0);
  EXPECT_EQ(score->tally.objects().at(1).add_correct, 2u);
}

TEST(DatasetScoring, WithoutTheCutTheLowerScoredEstimateWouldCount) {
  // b's estimate alone in its image is kept: 30 mm is past 17.3 (ADD) but within 0.2 diameters.
  test::TempDir dir;
  WriteDataset(dir.path());
  const auto score = Score(dir.path(), Row(0, 0, 1, 0.8, 230));
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  EXPECT_EQ(score->tally.overall().add_correct, 0u);
  EXPECT_EQ(score->tally.overall().mssd_correct, (std::vector<uint64_t>{0, 0, 0, 1, 1, 1, 1, 1, 1, 1}));
}

TEST(DatasetScoring, ThresholdsAreFractionsOfModelsInfoDiameter) {
  // 30 mm is past 10% of the cube's 173 mm but within 10% of the 400 mm models_info.json gives.
  test::TempDir dir;
  WriteDataset(dir.path());
  Write(dir.path() / "models/models_info.json", R"({"1": {"diameter": 400}})");
  const auto score = Score(dir.path(), Row(0, 0, 1, 0.8, 230));
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  EXPECT_EQ(score->tally.overall().add_correct, 1u);
  EXPECT_EQ(score->tally.overall().mssd_correct, (std::vector<uint64_t>{0, 1, 1, 1, 1, 1, 1, 1, 1, 1}));
}

TEST(DatasetScoring, TallyLeavesRecallUnsetWithoutValidInstances) {
  DatasetScoreTally tally(2);
  tally.AddObject(4);
  localization::ScanScore image;
  localization::PartScore part;
  part.part_id = 3;
  part.valid_instances = 4;
  part.add_correct = 1;
  part.mssd_recalls = {0.25, 0.75};
  image.parts.push_back(part);
  tally.AddImage(9, image);
  tally.AddImage(9, image);
  EXPECT_FALSE(tally.objects().at(4).AddRecall().has_value());
  EXPECT_TRUE(tally.objects().at(4).MssdRecalls().empty());
  EXPECT_EQ(tally.scenes().at(9).mssd_correct, (std::vector<uint64_t>{2, 6}));
  EXPECT_DOUBLE_EQ(*tally.overall().AddRecall(), 0.25);
  EXPECT_DOUBLE_EQ(*tally.overall().MssdAverageRecall(), 0.5);

  // Past max_scenes a scene counts overall and per object only.
  DatasetScoreTally bounded(2, 5);
  bounded.AddScene(4);
  bounded.AddScene(5);
  bounded.AddImage(4, image);
  bounded.AddImage(7, image);
  bounded.AddEstimates(9, 3, 2);
  EXPECT_EQ(bounded.scenes().size(), 1u);
  EXPECT_EQ(bounded.scenes().at(4).valid_instances, 4u);
  EXPECT_EQ(bounded.overall().valid_instances, 8u);
  EXPECT_EQ(bounded.objects().at(3).valid_instances, 8u);
  EXPECT_EQ(bounded.objects().at(3).estimates, 2u);
}

TEST(DatasetScoring, Refusals) {
  test::TempDir dir;
  WriteDataset(dir.path());
  const auto unknown = Score(dir.path(), Row(0, 0, 1, 1, 0) + Row(0, 0, 9, 1, 0));
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.status().message().find("line 2, column 3 (obj_id): obj_id 9 is not a part type"),
            std::string::npos)
      << unknown.status().message();

  DatasetScoringOptions tight;
  tight.max_work = 10;
  const auto costly = Score(dir.path(), kResults, tight);
  ASSERT_FALSE(costly.ok());
  EXPECT_EQ(costly.status().code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(costly.status().field(), "results_csv");

  std::atomic<bool> cancel{true};
  DatasetScoringOptions cancelled;
  cancelled.cancel = &cancel;
  EXPECT_EQ(Score(dir.path(), kResults, cancelled).status().code(), StatusCode::kCancelled);

  Write(dir.path() / "train_pbr/000001/scene_gt_info.json", R"({"0": [{"visib_fract": 1.5}]})");
  const auto damaged = Score(dir.path(), kResults);
  EXPECT_EQ(damaged.status().code(), StatusCode::kDataLoss);
  EXPECT_NE(damaged.status().message().find("000001/scene_gt_info.json"), std::string::npos);

  fs::remove(dir.path() / "scenes.json");
  EXPECT_EQ(Score(dir.path(), kResults).status().code(), StatusCode::kFailedPrecondition);
}

// The cube with its 12 triangles, so that grasps can be generated on it (millimetres).
void WriteCubeMesh(const fs::path& root) {
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 8; ++i) {
    ply += std::to_string(i & 1 ? 50 : -50) + " " + std::to_string(i & 2 ? 50 : -50) + " " +
           std::to_string(i & 4 ? 50 : -50) + "\n";
  }
  // Outward winding: -z, +z, -y, +y, -x, +x.
  for (const char* face : {"3 0 2 1", "3 1 2 3", "3 4 5 6", "3 5 7 6", "3 0 1 4", "3 1 5 4", "3 2 6 3", "3 3 6 7",
                           "3 0 4 2", "3 2 4 6", "3 1 3 5", "3 3 7 5"}) {
    ply += std::string(face) + "\n";
  }
  Write(root / "models/obj_000001.ply", ply);
}

std::string RowAt(int scene, int im, double score, double x, double z) {
  return std::to_string(scene) + "," + std::to_string(im) + ",1," + std::to_string(score) + ",1 0 0 0 1 0 0 0 1," +
         std::to_string(x) + " 0 " + std::to_string(z) + ",-1\n";
}

TEST(DatasetScoring, GraspSuccessCountsHeldGraspsOverValidInstances) {
  test::TempDir dir;
  WriteDataset(dir.path());
  WriteCubeMesh(dir.path());
  DatasetScoringOptions options;
  GraspScoring grasp;
  grasping::SuctionCup cup;
  cup.diameter_m = 0.02;
  grasp.gripper = cup;
  grasp.up = -Eigen::Vector3d::UnitZ();  // the camera looks down its +z onto the cube's near face
  options.grasp = grasp;
  // a exact (holds); d 10 mm sideways on a 100 mm face (holds); e 5 mm towards the camera: matched
  // (5 mm is within 10% of 173 mm) but the cup stops short of the true face.
  const std::string results = RowAt(0, 0, 0.9, 0, 500) + RowAt(0, 1, 0.5, 10, 500) + RowAt(1, 0, 0.5, 0, 495);
  const auto score = Score(dir.path(), results, options);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  const RecallCounts& overall = score->tally.overall();
  EXPECT_EQ(overall.valid_instances, 4u);  // a, b, d, e
  EXPECT_EQ(overall.add_correct, 3u);
  EXPECT_EQ(overall.grasp_holds, 2u);
  EXPECT_DOUBLE_EQ(*overall.GraspSuccess(), 0.5);
  EXPECT_EQ(score->tally.scenes().at(0).grasp_holds, 2u);
  EXPECT_EQ(score->tally.scenes().at(1).grasp_holds, 0u);
  EXPECT_DOUBLE_EQ(*score->tally.scenes().at(1).GraspSuccess(), 0.0);
  EXPECT_EQ(score->tally.objects().at(1).grasp_holds, 2u);
  // Without a gripper the same rows hold nothing and cost no grasp work.
  const auto plain = Score(dir.path(), results);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->tally.overall().grasp_holds, 0u);
  EXPECT_EQ(plain->tally.overall().add_correct, 3u);
  EXPECT_LT(plain->work, score->work);
  // The grasps' work counts in the bound: refused where the scoring alone fits.
  options.max_work = plain->work + 1000;
  EXPECT_EQ(Score(dir.path(), results, options).status().code(), StatusCode::kResourceExhausted);
}

TEST(DatasetScoring, AModelWithoutTrianglesIsDataLossWithAGripper) {
  test::TempDir dir;
  WriteDataset(dir.path());  // vertices only
  DatasetScoringOptions options;
  options.grasp = GraspScoring{grasping::SuctionCup{}, {}, Eigen::Vector3d::UnitZ()};
  const auto score = Score(dir.path(), RowAt(0, 0, 0.9, 0, 500), options);
  EXPECT_EQ(score.status().code(), StatusCode::kDataLoss);
  EXPECT_NE(score.status().message().find("obj_000001.ply"), std::string::npos) << score.status().ToString();
}

}  // namespace
}  // namespace vscan::service
