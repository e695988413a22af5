// One scene written and read back: depth and instance images, masks, cloud and record agree with
// the frame that went in.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/durable_file.h"
#include "service/datasets/format/models_info.h"
#include "service/datasets/format/scene_record.h"
#include "service/datasets/format/scene_writer.h"
#include "synthetic_bin.h"
#include "vscan/common/cloud_io.h"
#include "vscan/common/png_codec.h"
#include "vscan_test/temp_dir.h"

namespace vscan::service::dataset {
namespace {

DatasetPlan OneScenePlan() {
  DatasetPlan plan;
  plan.bins = {"bin"};
  plan.seeds = {3};
  plan.sensors = {"cam"};
  return plan;
}

GrayPixels ReadPng(const std::filesystem::path& path) {
  StatusOr<std::string> bytes = ReadWholeFile(path);
  EXPECT_TRUE(bytes.ok()) << path;
  if (!bytes.ok()) return {};
  StatusOr<GrayPixels> image = DecodeGrayPng(*bytes);
  EXPECT_TRUE(image.ok()) << path << ": " << image.status().ToString();
  return image.ok() ? *image : GrayPixels{};
}

class SceneWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    key_ = SceneAt(plan_, 0);
    frame_ = test::SyntheticFrame(key_);
  }
  std::filesystem::path Scene() const { return SceneDir(dir_.path(), 0); }

  test::TempDir dir_;
  DatasetPlan plan_ = OneScenePlan();
  SceneKey key_;
  DatasetFrame frame_;
};

TEST_F(SceneWriterTest, DepthComesBackInTenthsOfMillimetres) {
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  const GrayPixels depth = ReadPng(Scene() / "depth/000000.png");
  ASSERT_EQ(depth.bit_depth, 16);
  ASSERT_EQ(depth.width, frame_.camera.width);
  ASSERT_EQ(depth.height, frame_.camera.height);
  size_t measured = 0, empty = 0;
  for (size_t i = 0; i < depth.values.size(); ++i) {
    if (frame_.depth_m[i] == 0) {
      EXPECT_EQ(depth.values[i], 0) << i;
      ++empty;
      continue;
    }
    ++measured;
    EXPECT_NEAR(depth.values[i] * plan_.depth_scale_mm / 1000.0, frame_.depth_m[i], 0.05e-3) << i;
  }
  EXPECT_GT(measured, 0u);
  EXPECT_GT(empty, 0u) << "the synthetic view should see past the floor";
}

TEST_F(SceneWriterTest, InstanceImageAndMasksShowEachObjectWhereItIsSeen) {
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  const GrayPixels instances = ReadPng(Scene() / "instances/000000.png");
  ASSERT_EQ(instances.values.size(), frame_.instance_ids.size());
  ASSERT_EQ(frame_.objects.size(), 2u);
  for (size_t object = 0; object < frame_.objects.size(); ++object) {
    const GrayPixels mask = ReadPng(Scene() / ("mask_visib/000000_00000" + std::to_string(object) + ".png"));
    ASSERT_EQ(mask.bit_depth, 8);
    uint64_t count = 0;
    for (size_t i = 0; i < mask.values.size(); ++i) {
      const bool here = frame_.instance_ids[i] == frame_.objects[object].instance_id;
      EXPECT_EQ(mask.values[i], here ? 255 : 0) << i;
      if (here) {
        EXPECT_EQ(instances.values[i], object + 1) << i;
      }
      count += here ? 1 : 0;
    }
    EXPECT_EQ(count, frame_.objects[object].visible_pixels);
    EXPECT_GT(count, 0u);
  }
  for (size_t i = 0; i < instances.values.size(); ++i) {
    const bool floor_or_nothing = frame_.instance_ids[i] == test::kFloorInstance || frame_.instance_ids[i] == 0;
    if (floor_or_nothing) {
      EXPECT_EQ(instances.values[i], 0) << "the floor is no ground-truth object, pixel " << i;
    }
  }
}

TEST_F(SceneWriterTest, CloudKeepsPositionsNormalsAndInstancesOnly) {
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  StatusOr<PointCloud> cloud = ReadPly((Scene() / "cloud/000000.ply").string());
  ASSERT_TRUE(cloud.ok()) << cloud.status().ToString();
  EXPECT_EQ(cloud->fields, kFieldPosition | kFieldNormal | kFieldInstanceId);
  ASSERT_EQ(cloud->size(), frame_.cloud.size());
  for (size_t i = 0; i < cloud->size(); ++i) {
    EXPECT_EQ(cloud->positions[i], frame_.cloud.positions[i]);
    EXPECT_EQ(cloud->normals[i], frame_.cloud.normals[i]);
    EXPECT_EQ(cloud->instance_ids[i], frame_.cloud.instance_ids[i]);
  }
}

// Each placed part's material, when the frame carries them (the plan names any); none otherwise.
TEST_F(SceneWriterTest, MaterialsAreWrittenOnlyWhenTheFrameCarriesThem) {
  ASSERT_TRUE(frame_.materials.has_value());
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  StatusOr<std::string> written = ReadWholeFile(Scene() / kSceneMaterialsFile);
  ASSERT_TRUE(written.ok()) << written.status().ToString();
  EXPECT_EQ(*written, SceneMaterialsJson(*frame_.materials));
  for (const InstanceMaterial& instance : *frame_.materials) {
    EXPECT_NE(written->find("\"instance_id\":" + std::to_string(instance.instance_id)), std::string::npos);
  }
  std::filesystem::remove_all(Scene());
  DatasetFrame plain = frame_;
  plain.materials.reset();
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, plain).ok());
  EXPECT_FALSE(std::filesystem::exists(Scene() / kSceneMaterialsFile));
  EXPECT_TRUE(std::filesystem::exists(Scene() / kSceneFillFile));
}

TEST_F(SceneWriterTest, RecordListsEveryFileWithItsSizeAndChecksum) {
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  StatusOr<std::vector<SceneFileEntry>> files = ListSceneFiles(Scene());
  ASSERT_TRUE(files.ok());
  std::vector<std::string> names;
  for (const SceneFileEntry& file : *files) names.push_back(file.path);
  EXPECT_EQ(names, (std::vector<std::string>{"cloud/000000.ply", "depth/000000.png", "gray/000000.png",
                                             "instances/000000.png", "mask/000000_000000.png", "mask/000000_000001.png",
                                             "mask_visib/000000_000000.png", "mask_visib/000000_000001.png",
                                             "reasons/000000.png",
                                             "scene_camera.json", "scene_fill.json", "scene_gt.json",
                                             "scene_gt_info.json", "scene_materials.json"}));
  StatusOr<std::string> record = ReadWholeFile(Scene() / kSceneRecordFile);
  ASSERT_TRUE(record.ok());
  EXPECT_EQ(*record, SceneRecordJson(plan_, key_, *files));
  EXPECT_FALSE(std::filesystem::exists(PartialSceneDir(dir_.path(), 0)));
}

TEST_F(SceneWriterTest, ReplacesALeftoverPartialAndRefusesToOverwrite) {
  std::filesystem::create_directories(PartialSceneDir(dir_.path(), 0) / "depth");
  ASSERT_TRUE(WriteFileDurably(PartialSceneDir(dir_.path(), 0) / "stale.txt", "half").ok());
  ASSERT_TRUE(WriteScene(dir_.path(), plan_, key_, frame_).ok());
  EXPECT_FALSE(std::filesystem::exists(Scene() / "stale.txt"));
  EXPECT_EQ(WriteScene(dir_.path(), plan_, key_, frame_).code(), StatusCode::kAlreadyExists);
}

TEST_F(SceneWriterTest, RefusesAFrameWhoseCountsDisagreeAndWritesNothing) {
  frame_.objects[1].visible_pixels += 1;
  const Status status = WriteScene(dir_.path(), plan_, key_, frame_);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(status.field(), "objects[1].visible_pixels");
  EXPECT_FALSE(std::filesystem::exists(Scene()));
}

TEST_F(SceneWriterTest, DepthBeyondSixteenBitsIsOutOfRange) {
  frame_.depth_m[5] = 7.0f;  // 70000 tenths of a millimetre
  const Status status = WriteScene(dir_.path(), plan_, key_, frame_);
  EXPECT_EQ(status.code(), StatusCode::kOutOfRange);
  EXPECT_FALSE(std::filesystem::exists(Scene()));
}

TEST_F(SceneWriterTest, AMultiViewSceneIsPlacedOnlyOnceEveryViewIsIn) {
  plan_.views = {2, 30.0, 0.7, 0.9};
  StatusOr<SceneWriter> writer = SceneWriter::Begin(dir_.path(), plan_, key_);
  ASSERT_TRUE(writer.ok()) << writer.status().ToString();
  ASSERT_TRUE(writer->AddView(test::SyntheticFrame(plan_, key_, 0)).ok());
  EXPECT_EQ(writer->Finish().code(), StatusCode::kFailedPrecondition);
  EXPECT_FALSE(std::filesystem::exists(Scene()));
  ASSERT_TRUE(writer->AddView(test::SyntheticFrame(plan_, key_, 1)).ok());
  EXPECT_EQ(writer->AddView(test::SyntheticFrame(plan_, key_, 2)).code(), StatusCode::kFailedPrecondition);
  ASSERT_TRUE(writer->Finish().ok());
  EXPECT_TRUE(std::filesystem::exists(Scene() / "depth/000001.png"));
  EXPECT_FALSE(std::filesystem::exists(Scene() / "depth/000002.png"));
  EXPECT_FALSE(std::filesystem::exists(PartialSceneDir(dir_.path(), 0)));
  // Each view's depth is its own: the two images differ.
  EXPECT_NE(ReadPng(Scene() / "depth/000000.png").values, ReadPng(Scene() / "depth/000001.png").values);
}

TEST(ModelsInfo, DiameterAndBoundsOfABoxInMillimetres) {
  const std::vector<PartModel> parts = test::SyntheticParts();
  EXPECT_NEAR(MeshDiameter(parts[0].mesh), 2 * std::sqrt(0.08 * 0.08 + 0.05 * 0.05 + 0.03 * 0.03), 1e-6);
  PartModel repeated = parts[0];
  EXPECT_EQ(ModelsInfoJson({parts[0], repeated}).status().field(), "parts[1].obj_id");
}

}  // namespace
}  // namespace vscan::service::dataset
