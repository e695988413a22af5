#include <algorithm>
#include <atomic>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "raycast/cloud_append.h"
#include "raycast/scan_setup.h"
#include "raycast/scanner.h"
#include "vscan_test/meshes.h"

namespace vscan::raycast {
namespace {

// A sphere filling most of a view whose size is not a whole number of packets.
struct SphereView {
  std::shared_ptr<const RaycastScene> scene;
  sensor::PinholeCamera camera = sensor::CameraFromFov(203, 157, 50.0, 0.1, 10.0);
  Pose3 pose = Eigen::Translation3d(0.1, -0.2, 0.3) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());

  SphereView() {
    SceneInstance instance;
    instance.mesh = test::Share(test::MakeIcosphere(pose * Eigen::Vector3d(0, 0, 2.5), 0.9, 4));
    instance.instance_id = 7;
    const std::vector<SceneInstance> instances{instance};
    auto built = RaycastScene::Build(instances);
    EXPECT_TRUE(built.ok());
    scene = *built;
  }
};

// Appends blocks to a cloud; pauses the cast after `burst` blocks until WaitForRoom, where it may
// cancel the scan. HasRoom runs on the pipeline's input thread while Accept runs on its output
// thread, hence the atomic counter.
class RecordingSink final : public RowSink {
 public:
  RecordingSink(uint32_t fields, uint32_t burst) : burst_(burst) {
    cloud.fields = fields;
    ReserveForEveryPixel(cloud, 1 << 20);
  }
  void Accept(const RowBlock& block) override {
    EXPECT_EQ(block.first_row, rows) << "blocks arrive in row order";
    rows += block.rows;
    AppendRows(block, cloud);
    max_between_waits = std::max(max_between_waits, ++since_wait);
  }
  bool HasRoom() override { return since_wait.load() < burst_; }
  void WaitForRoom() override {
    ++waits;
    since_wait = 0;
    if (cancel_after_waits != 0 && waits == cancel_after_waits) cancel.store(true);
  }

  PointCloud cloud;
  uint32_t rows = 0;
  uint32_t waits = 0;
  std::atomic<uint32_t> since_wait{0};
  uint32_t max_between_waits = 0;
  uint32_t cancel_after_waits = 0;
  std::atomic<bool> cancel{false};

 private:
  uint32_t burst_;
};

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void ExpectSameCloud(const PointCloud& a, const PointCloud& b) {
  EXPECT_TRUE(SameBits(a.positions, b.positions));
  EXPECT_TRUE(SameBits(a.normals, b.normals));
  EXPECT_TRUE(SameBits(a.ranges, b.ranges));
  EXPECT_TRUE(SameBits(a.intensities, b.intensities));
  EXPECT_TRUE(SameBits(a.instance_ids, b.instance_ids));
  EXPECT_TRUE(SameBits(a.pixels, b.pixels));
}

TEST(ScanRowsTest, BlocksJoinedAreTheWholeCloudBitForBit) {
  SphereView view;
  ScanOptions options;
  options.fields = kFieldsAll;
  ScanStats whole_stats, stats;
  auto whole = Scan(*view.scene, view.camera, view.pose, options, &whole_stats);
  ASSERT_TRUE(whole.ok());
  ASSERT_GT(whole->size(), 10000u);

  RecordingSink sink(kFieldsAll, 1u << 30);
  ASSERT_TRUE(ScanRows(*view.scene, view.camera, view.pose, options, sink, &stats).ok());
  EXPECT_EQ(sink.rows, view.camera.height);
  EXPECT_EQ(stats.rows, view.camera.height);
  EXPECT_EQ(sink.waits, 0u);
  ExpectSameCloud(sink.cloud, *whole);
  EXPECT_EQ(stats.points, whole_stats.points);
  EXPECT_EQ(stats.min_range, whole_stats.min_range);
  EXPECT_EQ(stats.max_range, whole_stats.max_range);
}

TEST(ScanRowsTest, AFullSinkPausesTheCastWithoutChangingIt) {
  SphereView view;
  ScanOptions options;
  options.fields = kFieldPosition | kFieldPixel;
  options.frame = ScanFrame::kSensor;
  auto whole = Scan(*view.scene, view.camera, view.pose, options);
  ASSERT_TRUE(whole.ok());

  RecordingSink sink(options.fields, 2);
  ASSERT_TRUE(ScanRows(*view.scene, view.camera, view.pose, options, sink).ok());
  ExpectSameCloud(sink.cloud, *whole);
  // 40 strips, a pause after every 2; strips already started when the sink filled still arrive, so
  // a run between pauses holds at most the 2 plus the pipeline's tokens, however the threads race.
  const uint32_t strips = (view.camera.height + kPacketSide - 1) / kPacketSide;
  const uint32_t most_per_run = 2u + 4u * static_cast<uint32_t>(tbb::this_task_arena::max_concurrency());
  EXPECT_LE(sink.max_between_waits, most_per_run);
  EXPECT_GE(sink.waits, (strips + most_per_run - 1) / most_per_run - 1);
  EXPECT_LE(sink.waits, strips / 2);
}

TEST(ScanRowsTest, CancelWhilePausedStopsTheCast) {
  SphereView view;
  RecordingSink sink(kFieldsDefault, 1);
  sink.cancel_after_waits = 3;
  ScanOptions options;
  options.cancel = &sink.cancel;
  ScanStats stats;
  const Status status = ScanRows(*view.scene, view.camera, view.pose, options, sink, &stats);
  EXPECT_EQ(status.code(), StatusCode::kCancelled);
  EXPECT_EQ(stats.rows, sink.rows);
  EXPECT_GT(stats.rows, 0u);
  EXPECT_LT(stats.rows, view.camera.height / 2);
  EXPECT_EQ(stats.points, sink.cloud.size());
}

}  // namespace
}  // namespace vscan::raycast
