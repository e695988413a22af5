// Shard runs: a restarted run skips finished scenes and replaces half-written ones, two shards
// merged give the same bytes as one process, and the merge refuses an incomplete or damaged root.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <numeric>
#include <set>
#include <thread>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/dataset_merge.h"
#include "service/datasets/format/dataset_run.h"
#include "service/datasets/format/durable_file.h"
#include "synthetic_bin.h"
#include "vscan_test/temp_dir.h"

namespace vscan::service::dataset {
namespace {

DatasetPlan SmallPlan() { return test::SyntheticPlan(); }

// Every file under root by relative path, with its bytes.
std::map<std::string, std::string> Tree(const std::filesystem::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    StatusOr<std::string> bytes = ReadWholeFile(entry.path());
    EXPECT_TRUE(bytes.ok());
    files[entry.path().lexically_relative(root).generic_string()] = bytes.ok() ? *bytes : "";
  }
  return files;
}

// Counts the frames it hands out.
struct CountingSource {
  FrameSource Source() {
    return [this](const SceneKey& key, uint32_t) -> StatusOr<DatasetFrame> {
      scenes.push_back(key.scene_id);
      return test::SyntheticFrame(key);
    };
  }
  std::vector<uint64_t> scenes;
};

StatusOr<DatasetProgress> RunShard(const std::filesystem::path& root, const DatasetPlan& plan, uint32_t index,
                                   uint32_t count, const FrameSource& source) {
  ShardRun run;
  run.shard_index = index;
  run.shard_count = count;
  return RunDatasetShard(root, plan, test::SyntheticParts(), source, run);
}

TEST(DatasetRun, TwoShardsMergedMatchOneProcessByteForByte) {
  const DatasetPlan plan = SmallPlan();
  test::TempDir one, sharded;
  CountingSource all;
  ASSERT_TRUE(WriteDataset(one.path(), plan, test::SyntheticParts(), all.Source(), nullptr).ok());
  EXPECT_EQ(all.scenes.size(), SceneCount(plan));

  CountingSource first, second;
  StatusOr<DatasetProgress> shard1 = RunShard(sharded.path(), plan, 1, 2, second.Source());
  ASSERT_TRUE(shard1.ok()) << shard1.status().ToString();
  EXPECT_EQ(MergeDataset(sharded.path(), plan).code(), StatusCode::kFailedPrecondition) << "shard 0 has not run";
  StatusOr<DatasetProgress> shard0 = RunShard(sharded.path(), plan, 0, 2, first.Source());
  ASSERT_TRUE(shard0.ok()) << shard0.status().ToString();
  EXPECT_EQ(first.scenes, (std::vector<uint64_t>{0, 1, 2, 3, 8, 9, 10, 11}));
  EXPECT_EQ(second.scenes, (std::vector<uint64_t>{4, 5, 6, 7}));
  const Status merged = MergeDataset(sharded.path(), plan);
  ASSERT_TRUE(merged.ok()) << merged.ToString();

  const auto expected = Tree(one.path());
  const auto actual = Tree(sharded.path());
  EXPECT_TRUE(expected.contains("scenes.json"));
  EXPECT_TRUE(expected.contains("dataset.json"));
  EXPECT_TRUE(expected.contains("models/models_info.json"));
  EXPECT_TRUE(expected.contains("models/obj_000002.ply"));
  EXPECT_TRUE(expected.contains("train_pbr/000011/depth/000000.png"));
  ASSERT_EQ(expected.size(), actual.size());
  for (const auto& [path, bytes] : expected) {
    const auto found = actual.find(path);
    ASSERT_NE(found, actual.end()) << path;
    EXPECT_TRUE(found->second == bytes) << path << " differs";
  }
}

TEST(DatasetRun, EveryViewOfASceneLandsInItsDirectoryInOrderAndShardsMergeToTheSameBytes) {
  const DatasetPlan plan = test::SyntheticMultiViewPlan();
  test::TempDir one, sharded;
  std::mutex mutex;
  std::vector<std::pair<uint64_t, uint32_t>> asked;
  const FrameSource source = [&](const SceneKey& key, uint32_t view) -> StatusOr<DatasetFrame> {
    {
      const std::lock_guard lock(mutex);
      asked.emplace_back(key.scene_id, view);
    }
    return test::SyntheticFrame(plan, key, view);
  };
  ASSERT_TRUE(WriteDataset(one.path(), plan, test::SyntheticParts(), source, nullptr).ok());
  std::vector<std::pair<uint64_t, uint32_t>> expected;
  for (uint64_t id = 0; id < SceneCount(plan); ++id) {
    for (uint32_t view = 0; view < 3; ++view) expected.emplace_back(id, view);
  }
  EXPECT_EQ(asked, expected);
  const auto files = Tree(one.path());
  for (const char* path : {"train_pbr/000004/depth/000002.png", "train_pbr/000004/cloud/000001.ply",
                           "train_pbr/000004/mask_visib/000002_000001.png", "train_pbr/000004/mask/000000_000000.png"}) {
    EXPECT_TRUE(files.contains(path)) << path;
  }
  EXPECT_FALSE(files.contains("train_pbr/000004/depth/000003.png"));
  const std::string& cameras = files.at("train_pbr/000004/scene_camera.json");
  EXPECT_NE(cameras.find("\"2\":{"), std::string::npos) << cameras;
  EXPECT_EQ(cameras.find("\"3\":"), std::string::npos) << cameras;

  ShardRun run;
  run.frames_ahead = 4;
  for (const uint32_t index : {1u, 0u}) {
    run.shard_index = index;
    run.shard_count = 2;
    ASSERT_TRUE(RunDatasetShard(sharded.path(), plan, test::SyntheticParts(), test::SyntheticSource(plan), run).ok());
  }
  ASSERT_TRUE(MergeDataset(sharded.path(), plan).ok());
  EXPECT_EQ(Tree(sharded.path()), files);
}

TEST(DatasetRun, AFailedViewNamesSceneAndViewAndLeavesOnlyAPartialScene) {
  const DatasetPlan plan = test::SyntheticMultiViewPlan();
  test::TempDir root;
  const FrameSource source = [&plan](const SceneKey& key, uint32_t view) -> StatusOr<DatasetFrame> {
    if (key.scene_id == 1 && view == 2) return Internal("the scanner overheated");
    return test::SyntheticFrame(plan, key, view);
  };
  const Status status = RunShard(root.path(), plan, 0, 1, source).status();
  EXPECT_EQ(status.code(), StatusCode::kInternal);
  EXPECT_EQ(status.field(), "scenes[1].views[2]");
  EXPECT_TRUE(std::filesystem::exists(SceneDir(root.path(), 0)));
  EXPECT_FALSE(std::filesystem::exists(SceneDir(root.path(), 1)));
  // A rerun replaces the half-written scene and finishes the plan.
  ASSERT_TRUE(RunShard(root.path(), plan, 0, 1, test::SyntheticSource(plan)).ok());
  ASSERT_TRUE(MergeDataset(root.path(), plan).ok());
  EXPECT_FALSE(std::filesystem::exists(PartialSceneDir(root.path(), 1)));
}

TEST(DatasetRun, FramesCapturedAheadOnOtherThreadsWriteTheSameBytesInOrder) {
  const DatasetPlan plan = SmallPlan();
  test::TempDir sequential, ahead;
  ASSERT_TRUE(WriteDataset(sequential.path(), plan, test::SyntheticParts(), test::SyntheticSource(plan), nullptr).ok());

  std::mutex mutex;
  std::set<std::thread::id> threads;
  std::vector<uint64_t> written;
  ShardRun run;
  run.frames_ahead = 3;
  run.on_progress = [&](const DatasetProgress& p) { written.push_back(p.done); };
  const FrameSource source = [&](const SceneKey& key, uint32_t) {
    {
      const std::lock_guard lock(mutex);
      threads.insert(std::this_thread::get_id());
    }
    // Later scenes finish first, so the writer has to wait for the earlier ones.
    std::this_thread::sleep_for(std::chrono::milliseconds(2 * (12 - key.scene_id % 12)));
    return test::SyntheticFrame(key);
  };
  StatusOr<DatasetProgress> progress = RunDatasetShard(ahead.path(), plan, test::SyntheticParts(), source, run);
  ASSERT_TRUE(progress.ok()) << progress.status().ToString();
  ASSERT_TRUE(MergeDataset(ahead.path(), plan).ok());
  EXPECT_GT(threads.size(), 1u);
  std::vector<uint64_t> expected_done(SceneCount(plan) + 1);
  std::iota(expected_done.begin(), expected_done.end(), 0);
  EXPECT_EQ(written, expected_done);
  EXPECT_EQ(Tree(ahead.path()), Tree(sequential.path()));
}

TEST(DatasetRun, AFailedFrameStopsTheRunBeforeAnyLaterSceneIsWritten) {
  const DatasetPlan plan = SmallPlan();
  test::TempDir root;
  ShardRun run;
  run.frames_ahead = 4;
  const FrameSource source = [](const SceneKey& key, uint32_t) -> StatusOr<DatasetFrame> {
    if (key.scene_id == 3) return Internal("the bin would not settle");
    return test::SyntheticFrame(key);
  };
  StatusOr<DatasetProgress> progress = RunDatasetShard(root.path(), plan, test::SyntheticParts(), source, run);
  EXPECT_EQ(progress.status().code(), StatusCode::kInternal);
  EXPECT_NE(progress.status().ToString().find("scenes[3]"), std::string::npos) << progress.status().ToString();
  for (uint64_t id = 0; id < SceneCount(plan); ++id) {
    EXPECT_EQ(std::filesystem::exists(SceneDir(root.path(), id)), id < 3) << "scene " << id;
  }
}

TEST(DatasetRun, ARestartedRunSkipsFinishedScenesAndRedoesHalfWrittenOnes) {
  const DatasetPlan plan = SmallPlan();
  test::TempDir root;
  CountingSource source;
  ShardRun run;
  run.stop_requested = [&source] { return source.scenes.size() == 5; };
  StatusOr<DatasetProgress> stopped = RunDatasetShard(root.path(), plan, test::SyntheticParts(), source.Source(), run);
  EXPECT_EQ(stopped.status().code(), StatusCode::kCancelled);
  // A crash while scene 5 was being written leaves its partial directory behind.
  std::filesystem::create_directories(PartialSceneDir(root.path(), 5) / "depth");
  ASSERT_TRUE(WriteFileDurably(PartialSceneDir(root.path(), 5) / "depth/000000.png", "cut short").ok());

  CountingSource again;
  std::vector<DatasetProgress> reports;
  run.stop_requested = nullptr;
  run.on_progress = [&reports](const DatasetProgress& p) { reports.push_back(p); };
  StatusOr<DatasetProgress> resumed = RunDatasetShard(root.path(), plan, test::SyntheticParts(), again.Source(), run);
  ASSERT_TRUE(resumed.ok()) << resumed.status().ToString();
  EXPECT_EQ(again.scenes, (std::vector<uint64_t>{5, 6, 7, 8, 9, 10, 11}));
  EXPECT_EQ(resumed->skipped, 5u);
  EXPECT_EQ(resumed->written, 7u);
  EXPECT_EQ(resumed->done, 12u);
  EXPECT_EQ(resumed->total, 12u);
  // Seed 12's far-pair (scenes 6 and 7) took fewer parts than planned.
  EXPECT_EQ(resumed->underfilled, (std::vector<uint64_t>{6, 7}));
  ASSERT_EQ(reports.size(), 8u);
  for (size_t i = 0; i < reports.size(); ++i) {
    EXPECT_EQ(reports[i].done, 5 + i);
    EXPECT_EQ(reports[i].total, 12u);
  }
  EXPECT_FALSE(std::filesystem::exists(PartialSceneDir(root.path(), 5)));
  ASSERT_TRUE(MergeDataset(root.path(), plan).ok());

  CountingSource idle;
  StatusOr<DatasetProgress> nothing_left = RunShard(root.path(), plan, 0, 1, idle.Source());
  ASSERT_TRUE(nothing_left.ok());
  EXPECT_TRUE(idle.scenes.empty());
  EXPECT_EQ(nothing_left->skipped, 12u);
  // Found again in the scenes' scene_fill.json when no scene is written.
  EXPECT_EQ(nothing_left->underfilled, (std::vector<uint64_t>{6, 7}));
}

TEST(DatasetRun, APlanThatFailsOnUnderfilledBinsStopsAtTheFirstOne) {
  DatasetPlan plan = SmallPlan();
  plan.fail_on_underfilled_bin = true;
  test::TempDir root;
  CountingSource source;
  const Status status = RunShard(root.path(), plan, 0, 1, source.Source()).status();
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(status.ToString().find("scenes[6]: the bin took 2 of 3 parts"), std::string::npos) << status.ToString();
  EXPECT_NE(status.ToString().find("fail_on_underfilled_bin"), std::string::npos) << status.ToString();
  EXPECT_TRUE(std::filesystem::exists(SceneDir(root.path(), 5)));
  EXPECT_FALSE(std::filesystem::exists(SceneDir(root.path(), 6)));
}

TEST(DatasetRun, ARootOfAnotherPlanIsRefused) {
  test::TempDir root;
  CountingSource source;
  ASSERT_TRUE(RunShard(root.path(), SmallPlan(), 0, 2, source.Source()).ok());
  DatasetPlan other = SmallPlan();
  other.seeds = SeedRange(12, 3);
  EXPECT_EQ(RunShard(root.path(), other, 1, 2, source.Source()).status().code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(MergeDataset(root.path(), other).code(), StatusCode::kFailedPrecondition);
}

TEST(DatasetRun, AFailingSourceNamesItsScene) {
  test::TempDir root;
  const FrameSource failing = [](const SceneKey& key, uint32_t) -> StatusOr<DatasetFrame> {
    if (key.scene_id == 2) return Unavailable("the scanner is gone");
    return test::SyntheticFrame(key);
  };
  const Status status = RunShard(root.path(), SmallPlan(), 0, 1, failing).status();
  EXPECT_EQ(status.code(), StatusCode::kUnavailable);
  EXPECT_EQ(status.field(), "scenes[2]");
  EXPECT_TRUE(std::filesystem::exists(SceneDir(root.path(), 1)));
  EXPECT_FALSE(std::filesystem::exists(SceneDir(root.path(), 2)));
}

class MergeRefusalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    CountingSource source;
    ASSERT_TRUE(WriteDataset(root_.path(), plan_, test::SyntheticParts(), source.Source(), nullptr).ok());
  }
  std::filesystem::path Scene(uint64_t id) const { return SceneDir(root_.path(), id); }

  test::TempDir root_;
  DatasetPlan plan_ = SmallPlan();
};

TEST_F(MergeRefusalTest, AMissingSceneIsNamed) {
  std::filesystem::remove_all(Scene(7));
  const Status status = MergeDataset(root_.path(), plan_);
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(status.message(), "1 of 12 scenes are missing: 000007");
}

TEST_F(MergeRefusalTest, ALeftoverPartialDirectoryIsRefused) {
  std::filesystem::create_directories(PartialSceneDir(root_.path(), 3));
  const Status status = MergeDataset(root_.path(), plan_);
  EXPECT_EQ(status.code(), StatusCode::kFailedPrecondition);
  EXPECT_NE(status.message().find("000003.partial"), std::string::npos) << status.message();
}

TEST_F(MergeRefusalTest, AChangedByteIsDataLoss) {
  const auto path = Scene(4) / "depth/000000.png";
  StatusOr<std::string> bytes = ReadWholeFile(path);
  ASSERT_TRUE(bytes.ok());
  std::string damaged = *bytes;
  damaged[damaged.size() / 2] ^= 0x01;
  ASSERT_TRUE(WriteFileDurably(path, damaged).ok());
  EXPECT_EQ(MergeDataset(root_.path(), plan_).code(), StatusCode::kDataLoss);
}

TEST_F(MergeRefusalTest, AMissingOrExtraFileIsDataLoss) {
  std::filesystem::remove(Scene(2) / "mask_visib/000000_000001.png");
  EXPECT_EQ(MergeDataset(root_.path(), plan_).code(), StatusCode::kDataLoss);
  test::TempDir other;
  CountingSource source;
  ASSERT_TRUE(WriteDataset(other.path(), plan_, test::SyntheticParts(), source.Source(), nullptr).ok());
  ASSERT_TRUE(WriteFileDurably(SceneDir(other.path(), 0) / "notes.txt", "extra").ok());
  EXPECT_EQ(MergeDataset(other.path(), plan_).code(), StatusCode::kDataLoss);
}

TEST_F(MergeRefusalTest, AnotherScenesDirectoryUnderThisNameIsDataLoss) {
  std::filesystem::remove_all(Scene(1));
  std::filesystem::copy(Scene(0), Scene(1), std::filesystem::copy_options::recursive);
  EXPECT_EQ(MergeDataset(root_.path(), plan_).code(), StatusCode::kDataLoss);
}

}  // namespace
}  // namespace vscan::service::dataset
