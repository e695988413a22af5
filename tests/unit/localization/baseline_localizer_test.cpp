#include "localization/baseline_localizer.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "localization/bop_scoring.h"
#include "localization/pose_errors.h"
#include "parts_scene.h"
#include "raycast/raycast_scene.h"
#include "raycast/scanner.h"
#include "sensor/camera.h"
#include "vscan_test/meshes.h"

namespace vscan::localization {
namespace {

using testing::AngleBlock;
using testing::FixturePart;
using testing::LoadPart;
using testing::LyingParts;
using testing::PlacedPart;
using testing::ScanFloor;
using testing::ScanParts;
using testing::StandingPoses;
using testing::SymmetriesOf;

struct Scored {
  LocalizationResult found;
  ScanScore score;
};

Scored LocalizeAndScore(const std::vector<Pose3>& truth_poses) {
  const PointCloud scan = ScanParts(truth_poses, 0.2);
  EXPECT_GT(scan.size(), 10000u);
  auto found = LocalizeInstances(*AngleBlock(), scan);
  EXPECT_TRUE(found.ok()) << found.status().ToString();
  if (!found.ok()) return {};
  std::vector<PartDefinition> parts{{1, AngleBlock()->vertices, {}}};
  std::vector<TrueInstance> truth;
  for (const Pose3& pose : truth_poses) truth.push_back({1, pose, 1.0});
  std::vector<EstimatedInstance> estimates;
  for (const auto& instance : found->instances) estimates.push_back({1, instance.world_from_part, instance.score});
  auto score = ScoreScan(parts, truth, estimates);
  EXPECT_TRUE(score.ok()) << score.status().ToString();
  return {*found, score.ok() ? *score : ScanScore{}};
}

TEST(BaselineLocalizer, FindsThreeCopiesOnAPlate) {
  const std::vector<Pose3> truth = StandingPoses(3);
  const Scored result = LocalizeAndScore(truth);
  EXPECT_EQ(result.found.instances.size(), 3u) << result.found.parts.front().stop_reason;
  ASSERT_EQ(result.score.parts.size(), 1u);
  const PartScore& part = result.score.parts[0];
  EXPECT_EQ(part.add_recall, 1.0);
  EXPECT_EQ(part.mssd_average_recall, 1.0);
  // Noise-free: well under a millimetre of ADD against a 10% threshold of about 5 mm.
  for (const InstanceResult& instance : part.instances) {
    EXPECT_TRUE(instance.estimate_index.has_value());
    EXPECT_LT(instance.add_error, 0.0005);
  }
  for (const auto& instance : result.found.instances) {
    EXPECT_GT(instance.score, 0.2);
    EXPECT_GT(instance.explained_points, 1000u);
  }
}

// Localizes every kind of part the floor holds and scores all of them together.
ScanScore LocalizeFloor(const std::vector<PlacedPart>& placed, const PointCloud& scan,
                        const LocalizerOptions& options = {}) {
  std::vector<PartDefinition> parts;
  std::vector<TrueInstance> truth;
  std::vector<EstimatedInstance> estimates;
  for (const PlacedPart& p : placed) {
    const auto id = static_cast<uint32_t>(p.part) + 1;
    truth.push_back({id, p.world_from_part, 1.0});
    if (std::any_of(parts.begin(), parts.end(), [&](const PartDefinition& d) { return d.part_id == id; })) continue;
    parts.push_back({id, LoadPart(p.part)->vertices, SymmetriesOf(p.part)});
    auto found = LocalizeInstances(*LoadPart(p.part), scan, options);
    EXPECT_TRUE(found.ok()) << found.status().ToString();
    if (!found.ok()) continue;
    for (const auto& instance : found->instances) estimates.push_back({id, instance.world_from_part, instance.score});
  }
  auto score = ScoreScan(parts, truth, estimates);
  EXPECT_TRUE(score.ok()) << score.status().ToString();
  return score.ok() ? *score : ScanScore{};
}

TEST(BaselineLocalizer, FindsAngleBlocksLyingOnAFloor) {
  const std::vector<PlacedPart> placed = LyingParts({{FixturePart::kAngleBlock, 5}}, 0.2, 1);
  ASSERT_EQ(placed.size(), 5u);
  const ScanScore score = LocalizeFloor(placed, ScanFloor(placed, 0.2, 640, 480));
  ASSERT_TRUE(score.add_recall.has_value());
  EXPECT_GE(*score.add_recall, 0.8);
  EXPECT_GE(*score.mssd_average_recall, 0.7);
}

TEST(BaselineLocalizer, FindsTubesLyingOnAFloorUpToTheirSymmetry) {
  const std::vector<PlacedPart> placed = LyingParts({{FixturePart::kRound, 3}}, 1.0, 2);
  ASSERT_EQ(placed.size(), 3u);
  const ScanScore score = LocalizeFloor(placed, ScanFloor(placed, 1.0, 640, 480));
  ASSERT_EQ(score.parts.size(), 1u);
  EXPECT_TRUE(score.parts[0].uses_add_s);
  ASSERT_TRUE(score.add_recall.has_value());
  EXPECT_GE(*score.add_recall, 0.8);
}

TEST(BaselineLocalizer, FindsNoTubeAmongPlates) {
  const std::vector<PlacedPart> plates = LyingParts({{FixturePart::kPlateHoles, 3}}, 1.0, 3);
  ASSERT_EQ(plates.size(), 3u);
  auto found = LocalizeInstances(*LoadPart(FixturePart::kRound), ScanFloor(plates, 1.0, 640, 480));
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_TRUE(found->instances.empty()) << found->instances.size() << " tubes found, the first scoring "
                                        << found->instances.front().score;
}

// The same scenes with the sensor's position given: candidates ranked and checked by what it saw.
LocalizerOptions WithSensorOf(double floor_side) {
  LocalizerOptions options;
  options.sensor_position = testing::FloorSensorPose(floor_side).translation();
  return options;
}

TEST(BaselineLocalizer, FindsAngleBlocksLyingOnAFloorWithTheSensorsView) {
  const std::vector<PlacedPart> placed = LyingParts({{FixturePart::kAngleBlock, 5}}, 0.2, 1);
  const ScanScore score = LocalizeFloor(placed, ScanFloor(placed, 0.2, 640, 480), WithSensorOf(0.2));
  ASSERT_TRUE(score.add_recall.has_value());
  EXPECT_GE(*score.add_recall, 0.8);
  EXPECT_GE(*score.mssd_average_recall, 0.7);
}

TEST(BaselineLocalizer, FindsTubesAmongAngleBlocksWithTheSensorsView) {
  const std::vector<PlacedPart> placed =
      LyingParts({{FixturePart::kRound, 3}, {FixturePart::kAngleBlock, 6}}, 1.0, 2);
  const ScanScore score = LocalizeFloor(placed, ScanFloor(placed, 1.0, 640, 480), WithSensorOf(1.0));
  ASSERT_EQ(score.parts.size(), 2u);
  for (const PartScore& part : score.parts) {
    if (!part.uses_add_s) continue;
    ASSERT_TRUE(part.add_recall.has_value());
    EXPECT_GE(*part.add_recall, 0.6);
  }
}

// Three pins (the tube at 0.127: 77 mm long, 6.5 mm across) lying on a floor beside six angle
// blocks, seen from 0.45 m at 1280 x 960 as in a filled bin. Votes alone rank the pins' poses below
// hundreds of fits onto the blocks and the floor's edges.
constexpr double kPinFloor = 0.3, kPinScale = 0.127;

struct PinsAndBlocks {
  std::shared_ptr<TriangleMesh> pin;
  std::vector<Pose3> pins, blocks;
  PointCloud scan;
};

PinsAndBlocks ScanPinsAndBlocks() {
  PinsAndBlocks scene;
  scene.pin = std::make_shared<TriangleMesh>(*LoadPart(FixturePart::kRound));
  for (auto& v : scene.pin->vertices) v *= static_cast<float>(kPinScale);
  const double radius = 0.0254 * kPinScale;
  const std::vector<PlacedPart> blocks = LyingParts({{FixturePart::kAngleBlock, 6}}, 0.2, 4);
  std::vector<raycast::SceneInstance> instances = testing::FloorInstances(blocks, kPinFloor);
  for (const PlacedPart& block : blocks) scene.blocks.push_back(block.world_from_part);
  for (const Eigen::Vector2d& at : {Eigen::Vector2d(-0.12, 0.125), Eigen::Vector2d(0.03, 0.125),
                                    Eigen::Vector2d(-0.04, -0.13)}) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(at.x(), at.y(), radius);
    scene.pins.push_back(pose);
    instances.push_back({scene.pin, pose, 1.0, static_cast<uint32_t>(100 + scene.pins.size())});
  }
  auto built = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(built.ok()) << built.status().ToString();
  if (!built.ok()) return scene;
  raycast::ScanOptions scan_options;
  scan_options.fields = kFieldPosition | kFieldNormal;
  auto scan = raycast::Scan(**built, sensor::CameraFromFov(1280, 960, 50, 0.05, 4 * kPinFloor),
                            testing::FloorSensorPose(kPinFloor), scan_options);
  EXPECT_TRUE(scan.ok()) << scan.status().ToString();
  if (scan.ok()) scene.scan = std::move(*scan);
  return scene;
}

PartDefinition PinDefinition(const TriangleMesh& pin, uint32_t id) {
  PartSymmetries symmetries = SymmetriesOf(FixturePart::kRound);
  for (Pose3& flip : symmetries.discrete) flip.translation() *= kPinScale;
  for (auto& axis : symmetries.continuous) axis.point *= kPinScale;
  return {id, pin.vertices, symmetries};
}

TEST(BaselineLocalizer, FindsPinsBesideAngleBlocksWithTheSensorsView) {
  const PinsAndBlocks scene = ScanPinsAndBlocks();
  ASSERT_GT(scene.scan.size(), 100000u);
  LocalizerOptions options = WithSensorOf(kPinFloor);
  options.max_instances = 3;
  auto found = LocalizeInstances(*scene.pin, scene.scan, options);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  std::vector<PartDefinition> parts{PinDefinition(*scene.pin, 1)};
  std::vector<TrueInstance> truth;
  for (const Pose3& pose : scene.pins) truth.push_back({1, pose, 1.0});
  std::vector<EstimatedInstance> estimates;
  for (const auto& instance : found->instances) estimates.push_back({1, instance.world_from_part, instance.score});
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  ASSERT_TRUE(score->add_recall.has_value());
  EXPECT_GE(*score->add_recall, 2.0 / 3) << found->instances.size() << " found; " << found->parts.front().stop_reason;
}

// Both part types in one call: every instance carries the index of its part, and each part's
// instances are scored against that part's truth only.
TEST(BaselineLocalizer, FindsSeveralPartTypesInOneCall) {
  const PinsAndBlocks scene = ScanPinsAndBlocks();
  const std::vector<PartQuery> queries{{AngleBlock().get(), 6}, {scene.pin.get(), 3}};
  std::vector<LocalizeProgress> reports;
  auto found = LocalizeParts(queries, scene.scan.positions, scene.scan.normals, WithSensorOf(kPinFloor), nullptr,
                             [&](const LocalizeProgress& p) { reports.push_back(p); });
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  ASSERT_EQ(found->parts.size(), 2u);
  std::vector<PartDefinition> parts{{0, AngleBlock()->vertices, {}}, PinDefinition(*scene.pin, 1)};
  std::vector<TrueInstance> truth;
  for (const Pose3& pose : scene.blocks) truth.push_back({0, pose, 1.0});
  for (const Pose3& pose : scene.pins) truth.push_back({1, pose, 1.0});
  std::vector<EstimatedInstance> estimates;
  std::vector<size_t> per_part(2, 0);
  for (const auto& instance : found->instances) {
    ASSERT_LT(instance.part, 2u);
    ++per_part[instance.part];
    estimates.push_back({static_cast<uint32_t>(instance.part), instance.world_from_part, instance.score});
  }
  EXPECT_EQ(per_part[0], found->parts[0].found);
  EXPECT_EQ(per_part[1], found->parts[1].found);
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  ASSERT_EQ(score->parts.size(), 2u);
  EXPECT_GE(score->parts[0].add_recall.value_or(0), 0.8) << found->parts[0].stop_reason;
  EXPECT_GE(score->parts[1].add_recall.value_or(0), 2.0 / 3) << found->parts[1].stop_reason;
  ASSERT_FALSE(reports.empty());
  for (size_t i = 1; i < reports.size(); ++i) EXPECT_GE(reports[i].fraction, reports[i - 1].fraction);
  EXPECT_DOUBLE_EQ(reports.back().fraction, 1.0);
  EXPECT_EQ(reports.back().found, found->instances.size());
}

TEST(BaselineLocalizer, FindsNoTubeAmongPlatesWithTheSensorsView) {
  const std::vector<PlacedPart> plates = LyingParts({{FixturePart::kPlateHoles, 3}}, 1.0, 3);
  auto found = LocalizeInstances(*LoadPart(FixturePart::kRound), ScanFloor(plates, 1.0, 640, 480), WithSensorOf(1.0));
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_TRUE(found->instances.empty()) << found->instances.size() << " tubes found";
}

TEST(BaselineLocalizer, FindsNothingOnAnEmptyPlate) {
  const PointCloud scan = ScanParts({}, 0.2);
  auto found = LocalizeInstances(*AngleBlock(), scan.positions, scan.normals);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_TRUE(found->instances.empty());
  EXPECT_FALSE(found->parts.front().stop_reason.empty());
}

TEST(BaselineLocalizer, StopsAtMaxInstances) {
  const PointCloud scan = ScanParts(StandingPoses(2), 0.2);
  LocalizerOptions options;
  options.max_instances = 1;
  auto found = LocalizeInstances(*AngleBlock(), scan.positions, {}, options);
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  EXPECT_EQ(found->instances.size(), 1u);
  EXPECT_EQ(found->parts.front().stop_reason, "max_instances reached");
}

TEST(BaselineLocalizer, RejectsBadInputsAndHonoursCancel) {
  const std::vector<Eigen::Vector3f> points(200, Eigen::Vector3f::Zero());
  const std::vector<Eigen::Vector3f> normals(3, Eigen::Vector3f::UnitZ());
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, normals).status().field(), "scan_normals");
  LocalizerOptions options;
  options.min_score = 2;
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, {}, options).status().field(), "localizer.min_score");
  options = {};
  options.ppf_step_voxels = 0.5;
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, {}, options).status().field(), "localizer.ppf_step_voxels");
  options = {};
  options.sensor_position = Eigen::Vector3d(0, 0, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, {}, options).status().field(), "localizer.sensor_position");
  options = {};
  options.max_seen_through_share = 1.5;
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, {}, options).status().field(),
            "localizer.max_seen_through_share");
  std::atomic<bool> cancel{true};
  EXPECT_EQ(LocalizeInstances(*AngleBlock(), points, {}, {}, &cancel).status().code(), StatusCode::kCancelled);
  EXPECT_EQ(LocalizeParts({}, points, {}).status().field(), "parts");
  const std::vector<PartQuery> without_mesh{{AngleBlock().get(), 1}, {nullptr, 1}};
  EXPECT_EQ(LocalizeParts(without_mesh, points, {}).status().field(), "parts[1]");
}

// A long thin pin at the localizer's own voxel would leave thousands of points for the pair table:
// its step is coarsened to fit. A voxel the caller chose too fine is refused, naming it.
TEST(BaselineLocalizer, BoundsThePairTable) {
  const TriangleMesh pin =
      test::MakeBox(Eigen::Vector3d(-0.25, -0.0015, -0.0015), Eigen::Vector3d(0.25, 0.0015, 0.0015));
  const std::vector<Eigen::Vector3f> points(200, Eigen::Vector3f::Zero());
  EXPECT_TRUE(LocalizeInstances(pin, points, {}).ok());
  LocalizerOptions options;
  options.voxel_size = 1e-5;
  const auto refused = LocalizeInstances(*AngleBlock(), points, {}, options);
  EXPECT_EQ(refused.status().code(), StatusCode::kResourceExhausted) << refused.status().ToString();
  EXPECT_EQ(refused.status().field(), "options.voxel_size");
}

}  // namespace
}  // namespace vscan::localization
