// A scan through the service layer: a floor 1 m below the sensor, streamed row by row or handed
// over whole, cancelled, and refused for a scene that does not exist.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <optional>
#include <vector>

#include "service/scan/scan_run.h"
#include "service_world.h"

namespace vscan::service {
namespace {

constexpr uint32_t kWidth = 64;
constexpr uint32_t kHeight = 48;

// Records what a scan hands over, in order.
class RecordingConsumer final : public ScanConsumer {
 public:
  void Begin(uint64_t revision, std::optional<uint64_t> points) override {
    EXPECT_FALSE(begun) << "Begin twice";
    begun = true;
    scene_revision = revision;
    announced_points = points;
  }
  void Accept(const raycast::RowBlock& block) override {
    EXPECT_TRUE(begun) << "rows before Begin";
    EXPECT_EQ(block.first_row, next_row);
    next_row = block.first_row + block.rows;
    for (uint32_t r = 0; r < block.rows; ++r) {
      for (uint32_t i = 0; i < block.count[r]; ++i) {
        const float* p = block.positions + 3 * (size_t{r} * block.stride + i);
        z.push_back(p[2]);
      }
    }
  }
  bool HasRoom() override { return true; }
  void WaitForRoom() override {}
  Status Cloud(const PointCloud& cloud) override {
    EXPECT_TRUE(begun) << "cloud before Begin";
    ++clouds;
    for (const Eigen::Vector3f& p : cloud.positions) z.push_back(p.z());
    return Status::Ok();
  }

  bool begun = false;
  uint64_t scene_revision = 0;
  std::optional<uint64_t> announced_points;
  uint32_t next_row = 0;
  int clouds = 0;
  std::vector<float> z;
};

ScanPlan FloorPlan(const std::string& scene_id) {
  ScanPlan plan;
  plan.scene_id = scene_id;
  plan.camera = sensor::CameraFromFov(kWidth, kHeight, 60.0, 0.05, 5.0);
  plan.world_from_sensor =
      PoseFromLookAt(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY(), "pose").value();
  plan.fields = kFieldPosition;
  plan.measurement.fields = plan.fields;
  return plan;
}

void ExpectWholeFloor(const RecordingConsumer& out, const ScanOutcome& outcome) {
  // The floor fills the whole 60-degree frame: every ray hits it, at z = 0.
  EXPECT_EQ(out.z.size(), size_t{kWidth} * kHeight);
  EXPECT_EQ(outcome.stats.points, uint64_t{kWidth} * kHeight);
  for (float z : out.z) ASSERT_NEAR(z, 0.0f, 1e-5f);
  EXPECT_NEAR(outcome.stats.min_range, 1.0, 0.01);
  EXPECT_GT(outcome.stats.max_range, 1.0);
}

TEST(ScanRunTest, RaycastScanStreamsRowsInOrder) {
  testing::ServiceWorld world;
  const std::string scene = world.SceneWith(testing::FloorSquare(3.0), Pose3::Identity());
  RecordingConsumer out;
  ScanOutcome outcome;
  ASSERT_TRUE(RunScan(world.context(), FloorPlan(scene), nullptr, out, &outcome).ok());
  EXPECT_TRUE(outcome.streamed);
  EXPECT_FALSE(out.announced_points.has_value());  // unknown until the cast ends
  EXPECT_GT(out.scene_revision, 0u);
  EXPECT_EQ(out.next_row, kHeight);
  EXPECT_EQ(out.clouds, 0);
  ExpectWholeFloor(out, outcome);
}

TEST(ScanRunTest, WholeCloudScansHandTheCloudOverWithItsCount) {
  ServerOptions options;
  options.whole_cloud_scans = true;
  testing::ServiceWorld world(options);
  const std::string scene = world.SceneWith(testing::FloorSquare(3.0), Pose3::Identity());
  RecordingConsumer out;
  ScanOutcome outcome;
  ASSERT_TRUE(RunScan(world.context(), FloorPlan(scene), nullptr, out, &outcome).ok());
  EXPECT_FALSE(outcome.streamed);
  EXPECT_EQ(out.clouds, 1);
  EXPECT_EQ(out.announced_points, uint64_t{kWidth} * kHeight);
  ExpectWholeFloor(out, outcome);
}

TEST(ScanRunTest, MeasuredScansNeedTheWholeImage) {
  testing::ServiceWorld world;
  const std::string scene = world.SceneWith(testing::FloorSquare(3.0), Pose3::Identity());
  ScanPlan plan = FloorPlan(scene);
  plan.measurement.flying_pixels.enabled = true;  // no depth edge on a floor: every point stays
  EXPECT_FALSE(StreamsRows(plan, world.context().options));
  RecordingConsumer out;
  ScanOutcome outcome;
  ASSERT_TRUE(RunScan(world.context(), plan, nullptr, out, &outcome).ok());
  EXPECT_FALSE(outcome.streamed);
  EXPECT_EQ(out.clouds, 1);
  EXPECT_EQ(out.announced_points, out.z.size());
  ExpectWholeFloor(out, outcome);
}

TEST(ScanRunTest, ACancelledScanStopsWithCancelled) {
  testing::ServiceWorld world;
  const std::string scene = world.SceneWith(testing::FloorSquare(3.0), Pose3::Identity());
  const std::atomic<bool> cancel{true};
  RecordingConsumer out;
  ScanOutcome outcome;
  const Status status = RunScan(world.context(), FloorPlan(scene), &cancel, out, &outcome);
  EXPECT_EQ(status.code(), StatusCode::kCancelled) << status.ToString();
  EXPECT_LT(outcome.stats.rows, kHeight);
}

TEST(ScanRunTest, AnUnknownSceneIsNotFound) {
  testing::ServiceWorld world;
  RecordingConsumer out;
  ScanOutcome outcome;
  const Status status = RunScan(world.context(), FloorPlan("scn_0000000000000000"), nullptr, out, &outcome);
  EXPECT_EQ(status.code(), StatusCode::kNotFound) << status.ToString();
  EXPECT_FALSE(out.begun);
}

}  // namespace
}  // namespace vscan::service
