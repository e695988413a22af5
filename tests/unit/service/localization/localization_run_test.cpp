// Localize in the service layer: noise-free ray-cast scans of fixture parts lying on a floor,
// stored as uploaded clouds with their sensor pose, searched for one or two stored meshes through
// RunLocalize and the estimates scored through ScorePoses against the poses the parts were placed at.

#include <atomic>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "localization_fixture.h"
#include "service/clouds/cloud_store.h"
#include "service/localization/localization_run.h"
#include "service/localization/localization_scoring.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {
namespace {

using localization::testing::FixturePart;
using localization::testing::FloorSensorPose;
using localization::testing::LyingParts;
using localization::testing::PlacedPart;
using localization::testing::ScanFloor;

constexpr double kFloorSide = 0.2;

// The scan stored as an upload would be, with the sensor's pose; its true normals kept or dropped.
std::string StoreScan(testing::ServiceWorld& world, PointCloud scan, bool keep_normals,
                      double floor_side = kFloorSide) {
  if (!keep_normals) {
    scan.normals.clear();
    scan.fields &= ~kFieldNormal;
  }
  CloudUpload upload;
  upload.name = "floor";
  upload.format = CloudFileFormat::kPly;
  upload.world_from_sensor = FloorSensorPose(floor_side);
  auto record = ImportCloud(world.context(), *EncodePly(scan), upload);
  EXPECT_TRUE(record.ok()) << record.status().ToString();
  return record.ok() ? record->cloud_id : "";
}

// The estimates of one search scored against the placed angle blocks (no symmetry).
localization::ScanScore Score(testing::ServiceWorld& world, const std::string& mesh_id,
                              const std::vector<PlacedPart>& placed, const LocalizeOutcome& found) {
  ScoringPlan scoring;
  scoring.parts.push_back({mesh_id, 1, std::nullopt});
  for (const PlacedPart& p : placed) scoring.truth.push_back({0, p.world_from_part, 1.0});
  for (const auto& instance : found.result.instances) {
    scoring.estimates.push_back({0, instance.world_from_part, instance.score});
  }
  auto score = ScorePoses(world.context().registry, scoring);
  EXPECT_TRUE(score.ok()) << score.status().ToString();
  return score.ok() ? *score : localization::ScanScore{};
}

class LocalizationServiceRun : public ::testing::Test {
 protected:
  const std::string& block_id() const { return mesh_ids_[static_cast<size_t>(FixturePart::kAngleBlock)]; }

  LocalizePlan Plan(const std::string& cloud_id, NormalSource normals) const {
    LocalizePlan plan;
    plan.cloud_id = cloud_id;
    plan.parts = {{block_id()}};
    plan.normal_source = normals;
    return plan;
  }

  LocalizeOutcome Run(const LocalizePlan& plan) {
    auto found = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr);
    EXPECT_TRUE(found.ok()) << found.status().ToString();
    return found.ok() ? *found : LocalizeOutcome{};
  }

  testing::ServiceWorld world_;
  std::array<std::string, 3> mesh_ids_ = testing::StoreFixtureParts(world_);
};

TEST_F(LocalizationServiceRun, FindsLyingAngleBlocksInAStoredScanWithItsNormals) {
  const auto placed = LyingParts({{FixturePart::kAngleBlock, 5}}, kFloorSide, 1);
  const PointCloud scan = ScanFloor(placed, kFloorSide, 640, 480);
  const LocalizeOutcome found = Run(Plan(StoreScan(world_, scan, true), NormalSource::kCloud));
  EXPECT_EQ(found.points, scan.size());
  EXPECT_EQ(found.frame, store::CloudFrame::kWorld);
  EXPECT_GT(found.localize_ms, 0);
  const localization::ScanScore score = Score(world_, block_id(), placed, found);
  EXPECT_EQ(score.valid_instances, 5u);
  ASSERT_TRUE(score.add_recall.has_value());
  EXPECT_GE(*score.add_recall, 0.8);
  EXPECT_GE(*score.mssd_average_recall, 0.7);
}

// Without normals in the cloud they are estimated and turned towards the stored sensor position:
// the same search as with that position given, and a better one than with normals turned away.
TEST_F(LocalizationServiceRun, EstimatesNormalsTowardsTheStoredSensorPose) {
  const auto placed = LyingParts({{FixturePart::kAngleBlock, 5}}, kFloorSide, 1);
  const std::string cloud = StoreScan(world_, ScanFloor(placed, kFloorSide, 320, 240), false);

  const LocalizeOutcome by_default = Run(Plan(cloud, NormalSource::kAuto));
  const localization::ScanScore score = Score(world_, block_id(), placed, by_default);
  ASSERT_TRUE(score.add_recall.has_value());
  EXPECT_GE(*score.add_recall, 0.8);

  LocalizePlan at_sensor = Plan(cloud, NormalSource::kEstimate);
  at_sensor.viewpoint = FloorSensorPose(kFloorSide).translation();
  const LocalizeOutcome given = Run(at_sensor);
  ASSERT_EQ(given.result.instances.size(), by_default.result.instances.size());
  for (size_t i = 0; i < given.result.instances.size(); ++i) {
    EXPECT_TRUE(given.result.instances[i].world_from_part.isApprox(by_default.result.instances[i].world_from_part,
                                                                   1e-9))
        << "instance " << i;
  }

  LocalizePlan below_floor = Plan(cloud, NormalSource::kEstimate);
  below_floor.viewpoint = Eigen::Vector3d(0, 0, -1);
  const localization::ScanScore turned_away = Score(world_, block_id(), placed, Run(below_floor));
  EXPECT_LT(*turned_away.add_recall, *score.add_recall);
}

TEST_F(LocalizationServiceRun, RefusesUnknownMeshesAndCloudsAndMissingNormals) {
  LocalizePlan plan = Plan("cld_0000000000000000", NormalSource::kAuto);
  const auto no_cloud = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr);
  EXPECT_EQ(no_cloud.status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(no_cloud.status().message().starts_with("cloud_id")) << no_cloud.status().message();

  const auto placed = LyingParts({{FixturePart::kAngleBlock, 1}}, kFloorSide, 1);
  plan.cloud_id = StoreScan(world_, ScanFloor(placed, kFloorSide, 160, 120), false);
  plan.normal_source = NormalSource::kCloud;
  const auto no_normals = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr);
  EXPECT_EQ(no_normals.status().code(), StatusCode::kFailedPrecondition);
  EXPECT_TRUE(no_normals.status().message().starts_with("options.normal_source")) << no_normals.status().message();

  plan.normal_source = NormalSource::kAuto;
  plan.parts[0].mesh_id = "msh_0000000000000000";
  const auto no_mesh = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr);
  EXPECT_EQ(no_mesh.status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(no_mesh.status().message().starts_with("mesh_id")) << no_mesh.status().message();

  // In the list form the part's own field is named, and nothing is searched.
  plan.parts = {{block_id(), 1, 0, "parts[0].mesh_id"}, {"msh_0000000000000000", 2, 0, "parts[1].mesh_id"}};
  bool searched = false;
  const auto second = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr,
                                  [&](const localization::LocalizeProgress& p) { searched |= p.fraction > 0; });
  EXPECT_EQ(second.status().code(), StatusCode::kNotFound);
  EXPECT_TRUE(second.status().message().starts_with("parts[1].mesh_id")) << second.status().message();
  EXPECT_FALSE(searched);
}

// A part's own max_instances bounds its search below the options' one.
TEST_F(LocalizationServiceRun, StopsAPartAtItsOwnMaxInstances) {
  const auto placed = LyingParts({{FixturePart::kAngleBlock, 5}}, kFloorSide, 1);
  LocalizePlan plan = Plan(StoreScan(world_, ScanFloor(placed, kFloorSide, 320, 240), true), NormalSource::kCloud);
  plan.options.max_instances = 10;
  plan.parts[0].max_instances = 2;
  const LocalizeOutcome found = Run(plan);
  EXPECT_EQ(found.result.instances.size(), 2u);
  ASSERT_EQ(found.result.parts.size(), 1u);
  EXPECT_EQ(found.result.parts[0].found, 2u);
}

// Angle blocks and pins (the tube scaled to 0.127) in one call: each estimate carries its part's
// index, each part's instances score against that part's truth, and progress rises to 1.
TEST_F(LocalizationServiceRun, FindsTwoPartTypesInOneCall) {
  const testing::PinsAndBlocks scene = testing::ScanPinsBesideBlocks();
  ASSERT_GT(scene.scan.size(), 100000u);
  LocalizePlan plan = Plan(StoreScan(world_, scene.scan, true, testing::kPinFloor), NormalSource::kCloud);
  const std::string& round_id = mesh_ids_[static_cast<size_t>(FixturePart::kRound)];
  plan.parts = {{block_id(), 1, 6, "parts[0].mesh_id"}, {round_id, testing::kPinScale, 3, "parts[1].mesh_id"}};
  std::vector<localization::LocalizeProgress> reports;
  auto outcome = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr,
                             [&](const localization::LocalizeProgress& p) { reports.push_back(p); });
  ASSERT_TRUE(outcome.ok()) << outcome.status().ToString();
  const LocalizeOutcome& found = *outcome;
  ASSERT_EQ(found.result.parts.size(), 2u);

  ScoringPlan scoring;
  scoring.parts.push_back({block_id(), 1, std::nullopt});
  scoring.parts.push_back({round_id, testing::kPinScale, testing::PinSymmetries()});
  for (const Pose3& pose : scene.blocks) scoring.truth.push_back({0, pose, 1.0});
  for (const Pose3& pose : scene.pins) scoring.truth.push_back({1, pose, 1.0});
  std::vector<size_t> per_part(2, 0);
  for (const auto& instance : found.result.instances) {
    ASSERT_LT(instance.part, 2u);
    ++per_part[instance.part];
    scoring.estimates.push_back({static_cast<uint32_t>(instance.part), instance.world_from_part, instance.score});
  }
  EXPECT_EQ(per_part[0], found.result.parts[0].found);
  EXPECT_EQ(per_part[1], found.result.parts[1].found);
  EXPECT_LE(per_part[0], 6u);
  EXPECT_LE(per_part[1], 3u);
  auto score = ScorePoses(world_.context().registry, scoring);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  ASSERT_EQ(score->parts.size(), 2u);
  EXPECT_GE(score->parts[0].add_recall.value_or(0), 0.8) << found.result.parts[0].stop_reason;
  EXPECT_GE(score->parts[1].add_recall.value_or(0), 2.0 / 3) << found.result.parts[1].stop_reason;

  ASSERT_GE(reports.size(), 2u);
  EXPECT_EQ(reports.front().fraction, 0.0);
  for (size_t i = 1; i < reports.size(); ++i) EXPECT_GE(reports[i].fraction, reports[i - 1].fraction);
  EXPECT_DOUBLE_EQ(reports.back().fraction, 1.0);
  EXPECT_EQ(reports.back().found, found.result.instances.size());
}

TEST_F(LocalizationServiceRun, StopsWhenCancelled) {
  const auto placed = LyingParts({{FixturePart::kAngleBlock, 3}}, kFloorSide, 1);
  const std::atomic<bool> cancel{true};
  const LocalizePlan plan = Plan(StoreScan(world_, ScanFloor(placed, kFloorSide, 320, 240), true), NormalSource::kCloud);
  const auto found = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, &cancel);
  EXPECT_EQ(found.status().code(), StatusCode::kCancelled);
}

// A kept part model gives the same instances as one built for the call; it is kept per mesh, scale
// and options, and the least recently used leaves first.
TEST_F(LocalizationServiceRun, KeptPartModelsGiveTheSameInstances) {
  const auto placed = LyingParts({{FixturePart::kAngleBlock, 3}}, kFloorSide, 2);
  const LocalizePlan plan = Plan(StoreScan(world_, ScanFloor(placed, kFloorSide, 320, 240), true), NormalSource::kCloud);
  localization::PartModelCache models(2);
  const auto built = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr);
  const auto first = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr, {}, &models);
  const auto kept = RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), plan, nullptr, {}, &models);
  ASSERT_TRUE(built.ok() && first.ok() && kept.ok()) << built.status().ToString() << first.status().ToString();
  EXPECT_EQ(models.size(), 1u);
  ASSERT_FALSE(built->result.instances.empty());
  for (const auto* outcome : {&*first, &*kept}) {
    ASSERT_EQ(outcome->result.instances.size(), built->result.instances.size());
    for (size_t i = 0; i < built->result.instances.size(); ++i) {
      EXPECT_TRUE(outcome->result.instances[i].world_from_part.isApprox(built->result.instances[i].world_from_part, 1e-9));
    }
  }
  LocalizePlan other = plan;
  other.parts[0].scale = 1.5;
  ASSERT_TRUE(RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), other, nullptr, {}, &models).ok());
  other.options.voxel_size = 0.002;
  ASSERT_TRUE(RunLocalize(world_.context().registry, StoredCloudsOf(world_.context()), other, nullptr, {}, &models).ok());
  EXPECT_EQ(models.size(), 2u);
}


}  // namespace
}  // namespace vscan::service
