#include "localization/baseline_localizer.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "localization/bop_scoring.h"
#include "localization/pose_errors.h"
#include "made_parts.h"
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

// Votes alone rank the pins' poses below hundreds of fits onto the blocks and the floor's edges.
using testing::kPinFloor;
using testing::PinsBesideBlocks;
using testing::ScanPinsBesideBlocks;

PartDefinition PinDefinition(const TriangleMesh& pin, uint32_t id) { return {id, pin.vertices, testing::PinSymmetries()}; }

TEST(BaselineLocalizer, FindsPinsBesideAngleBlocksWithTheSensorsView) {
  const PinsBesideBlocks scene = ScanPinsBesideBlocks();
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
  const PinsBesideBlocks scene = ScanPinsBesideBlocks();
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

// Parts (mesh, pose) on a floor of side floor_side, seen from FloorSensorPose at 1280 x 960 as in
// a filled bin.
PointCloud ScanOnFloor(const std::vector<std::pair<std::shared_ptr<const TriangleMesh>, Pose3>>& parts,
                       double floor_side) {
  std::vector<raycast::SceneInstance> instances;
  for (size_t i = 0; i < parts.size(); ++i) {
    instances.push_back({parts[i].first, parts[i].second, 1.0, static_cast<uint32_t>(i + 1)});
  }
  instances.push_back({test::Share(test::MakeSquare(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), floor_side / 2)),
                       Pose3::Identity(), 1.0, 0});
  auto scene = raycast::RaycastScene::Build(instances);
  EXPECT_TRUE(scene.ok()) << scene.status().ToString();
  if (!scene.ok()) return {};
  raycast::ScanOptions scan_options;
  scan_options.fields = kFieldPosition | kFieldNormal;
  auto scan = raycast::Scan(**scene, sensor::CameraFromFov(1280, 960, 50, 0.05, 4 * floor_side),
                            testing::FloorSensorPose(floor_side), scan_options);
  EXPECT_TRUE(scan.ok()) << scan.status().ToString();
  return scan.ok() ? std::move(*scan) : PointCloud{};
}

// Lying on the floor at (x, y), turned by yaw about z.
Pose3 LyingAt(double x, double y, double yaw_deg) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, 0);
  return pose;
}

// The ADD(-S) recall of each part over the instances found, scored against the truth.
std::vector<double> RecallPerPart(const std::vector<PartDefinition>& parts, const std::vector<TrueInstance>& truth,
                                  const LocalizationResult& found) {
  std::vector<EstimatedInstance> estimates;
  for (const auto& i : found.instances) {
    estimates.push_back({parts[i.part].part_id, i.world_from_part, i.score});
  }
  auto score = ScoreScan(parts, truth, estimates);
  EXPECT_TRUE(score.ok()) << score.status().ToString();
  std::vector<double> recalls;
  if (!score.ok()) return recalls;
  for (const PartScore& part : score->parts) recalls.push_back(part.add_recall.value_or(0));
  return recalls;
}

// Parts the fixtures do not hold, four of each in one scan: a twelve-sided prism (a nut's hull), an
// L-shaped bracket with flat machined faces lying flat, and a thin square pin (3 mm across).
TEST(BaselineLocalizer, FindsMadePartsOfEveryKindInOneCall) {
  const testing::MadePart prism = testing::Prism(12, 0.012, 0.008);
  const testing::MadePart bracket = testing::Bracket(0.045, 0.03, 0.012, 0.004);
  const testing::MadePart pin = testing::SquarePin(0.05, 0.003);
  const std::vector<const testing::MadePart*> kinds = {&prism, &bracket, &pin};
  std::vector<std::pair<std::shared_ptr<const TriangleMesh>, Pose3>> placed;
  std::vector<TrueInstance> truth;
  const double yaws[] = {10, 75, 140, 205, 260, 320, 35, 100, 170, 230, 290, 355};
  for (int k = 0; k < 12; ++k) {
    const size_t kind = static_cast<size_t>(k % 3);
    const Pose3 pose = LyingAt(-0.105 + 0.07 * (k % 4), -0.07 + 0.07 * (k / 4), yaws[k]);
    placed.push_back({kinds[kind]->mesh, pose});
    truth.push_back({static_cast<uint32_t>(kind), pose, 1.0});
  }
  const PointCloud scan = ScanOnFloor(placed, 0.3);
  ASSERT_GT(scan.size(), 100000u);
  const std::vector<PartQuery> queries{{prism.mesh.get(), 4}, {bracket.mesh.get(), 4}, {pin.mesh.get(), 4}};
  auto found = LocalizeParts(queries, scan.positions, scan.normals, WithSensorOf(0.3));
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  std::vector<PartDefinition> parts;
  for (size_t kind = 0; kind < kinds.size(); ++kind) {
    parts.push_back({static_cast<uint32_t>(kind), kinds[kind]->mesh->vertices, kinds[kind]->symmetries});
  }
  const std::vector<double> recalls = RecallPerPart(parts, truth, *found);
  ASSERT_EQ(recalls.size(), 3u);
  EXPECT_GE(recalls[0], 0.75) << "prisms; " << found->parts[0].stop_reason;
  EXPECT_GE(recalls[1], 0.75) << "brackets; " << found->parts[1].stop_reason;
  EXPECT_GE(recalls[2], 0.75) << "pins; " << found->parts[2].stop_reason;
}

// The fixture plate (51 x 76 x 3.2 mm at 0.25) lying flat on the floor beside angle blocks: its top
// face alone gives only parallel-normal pairs; its rim is what finds it.
TEST(BaselineLocalizer, FindsPlatesLyingFlatBesideBlocks) {
  auto plate = std::make_shared<TriangleMesh>(*LoadPart(FixturePart::kPlateHoles));
  for (auto& v : plate->vertices) v *= 0.25f;
  std::vector<std::pair<std::shared_ptr<const TriangleMesh>, Pose3>> placed;
  std::vector<TrueInstance> truth;
  const double plate_yaws[] = {20, 110, 250};
  for (int k = 0; k < 3; ++k) {
    const Pose3 pose = LyingAt(-0.1 + 0.075 * k, -0.06, plate_yaws[k]);
    placed.push_back({plate, pose});
    truth.push_back({0, pose, 1.0});
  }
  for (const PlacedPart& block : LyingParts({{FixturePart::kAngleBlock, 3}}, 0.2, 7)) {
    if (block.world_from_part.translation().y() < 0.01) continue;  // the plates' half of the floor
    placed.push_back({AngleBlock(), block.world_from_part});
  }
  const PointCloud scan = ScanOnFloor(placed, 0.3);
  const std::vector<PartQuery> queries{{plate.get(), 3}, {AngleBlock().get(), 3}};
  auto found = LocalizeParts(queries, scan.positions, scan.normals, WithSensorOf(0.3));
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  // The plate's outline and holes turn onto themselves by half turns about its three central axes.
  PartSymmetries plate_symmetries;
  const Eigen::Vector3d centre = Eigen::Vector3d(0.2032, 0.3048, 0.0127) * 0.25 / 2;
  for (const Eigen::Vector3d& diagonal : {Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(1, -1, -1), Eigen::Vector3d(-1, 1, -1)}) {
    Pose3 turn = Pose3::Identity();
    turn.linear() = diagonal.asDiagonal();
    turn.translation() = centre - turn.linear() * centre;
    plate_symmetries.discrete.push_back(turn);
  }
  const std::vector<PartDefinition> parts{{0, plate->vertices, plate_symmetries}, {1, AngleBlock()->vertices, {}}};
  const std::vector<double> recalls = RecallPerPart(parts, truth, *found);
  ASSERT_EQ(recalls.size(), 2u);
  EXPECT_GE(recalls[0], 2.0 / 3) << found->parts[0].found << " plates found; " << found->parts[0].stop_reason;
}

// Six flat plates lying side by side, 2 mm apart: their top faces make one connected plane piece
// wider than any part, which is still parts, not a bin's rim or wall. Every plate is found where it
// lies; a 40 x 30 plate turned a quarter over its coplanar neighbours fits almost as well, so
// only half are found at their true turn (docs/LOCALIZATION.md, limits).
TEST(BaselineLocalizer, FindsPlatesLyingSideBySide) {
  const auto plate = test::Share(test::MakeBox(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.04, 0.03, 0.004)));
  std::vector<std::pair<std::shared_ptr<const TriangleMesh>, Pose3>> placed;
  std::vector<TrueInstance> truth;
  for (int k = 0; k < 6; ++k) {
    const Pose3 pose = LyingAt(-0.06 + 0.042 * (k % 3), -0.03 + 0.032 * (k / 3), 0);
    placed.push_back({plate, pose});
    truth.push_back({0, pose, 1.0});
  }
  const PointCloud scan = ScanOnFloor(placed, 0.3);
  const std::vector<PartQuery> queries{{plate.get(), 6}};
  auto found = LocalizeParts(queries, scan.positions, scan.normals, WithSensorOf(0.3));
  ASSERT_TRUE(found.ok()) << found.status().ToString();
  // The plate turns onto itself by half turns about its three central axes.
  PartSymmetries symmetries;
  const Eigen::Vector3d centre(0.02, 0.015, 0.002);
  for (const Eigen::Vector3d& diagonal : {Eigen::Vector3d(-1, -1, 1), Eigen::Vector3d(1, -1, -1), Eigen::Vector3d(-1, 1, -1)}) {
    Pose3 turn = Pose3::Identity();
    turn.linear() = diagonal.asDiagonal();
    turn.translation() = centre - turn.linear() * centre;
    symmetries.discrete.push_back(turn);
  }
  ASSERT_EQ(found->instances.size(), 6u) << found->parts[0].stop_reason;
  const Eigen::Vector3d centre_in_part = centre;
  for (const TrueInstance& t : truth) {
    double nearest = 1;
    for (const auto& i : found->instances) {
      nearest = std::min(nearest, (i.world_from_part * centre_in_part - t.world_from_part * centre_in_part).norm());
    }
    EXPECT_LT(nearest, 0.008) << "a plate at " << t.world_from_part.translation().transpose() << " has no estimate";
  }
  const std::vector<double> recalls = RecallPerPart({{0, plate->vertices, symmetries}}, truth, *found);
  ASSERT_EQ(recalls.size(), 1u);
  EXPECT_GE(recalls[0], 0.5) << found->parts[0].stop_reason;
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
