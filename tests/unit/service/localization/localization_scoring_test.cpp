// ScorePoses in the service layer on hand-made poses of stored fixture parts, checked against
// errors and diameters computed here from the parts' vertices: exact estimates, known offsets, a
// tube turned and flipped onto itself with and without its symmetries, and refused inputs.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "localization_fixture.h"
#include "service/localization/localization_scoring.h"

namespace vscan::service {
namespace {

using localization::testing::FixturePart;
using localization::testing::LoadPart;
using localization::testing::SymmetriesOf;

double Diameter(const TriangleMesh& mesh) {
  double largest = 0;
  for (const Eigen::Vector3f& a : mesh.vertices) {
    for (const Eigen::Vector3f& b : mesh.vertices) largest = std::max(largest, static_cast<double>((a - b).norm()));
  }
  return largest;
}

Pose3 Turned(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& translation) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

// Three blocks far apart (0.3 m, several diameters), each turned differently.
std::vector<Pose3> ThreeBlocks() {
  return {Pose3::Identity(), Turned(std::numbers::pi / 2, Eigen::Vector3d::UnitZ(), {0.3, 0, 0}),
          Turned(1.0, Eigen::Vector3d(1, 1, 0), {0, 0.3, 0.05})};
}

class LocalizationServiceScoring : public ::testing::Test {
 protected:
  const std::string& id(FixturePart part) const { return mesh_ids_[static_cast<size_t>(part)]; }

  testing::ServiceWorld world_;
  std::array<std::string, 3> mesh_ids_ = testing::StoreFixtureParts(world_);
};

TEST_F(LocalizationServiceScoring, ExactEstimatesScorePerfectly) {
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  for (const Pose3& pose : ThreeBlocks()) {
    plan.truth.push_back({0, pose, 1.0});
    plan.estimates.push_back({0, pose, 0.5});
  }
  const auto score = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  const localization::PartScore& part = score->parts[0];
  EXPECT_NEAR(part.diameter, Diameter(*LoadPart(FixturePart::kAngleBlock)), 1e-9);
  EXPECT_FALSE(part.uses_add_s);
  EXPECT_EQ(part.valid_instances, 3u);
  EXPECT_EQ(part.add_correct, 3u);
  EXPECT_EQ(*score->add_recall, 1.0);
  EXPECT_EQ(*score->mssd_average_recall, 1.0);
  EXPECT_EQ(part.mssd_recalls, std::vector<double>(10, 1.0));
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(part.instances[i].estimate_index, i);
    EXPECT_NEAR(part.instances[i].add_error, 0, 1e-9);
    EXPECT_NEAR(part.instances[i].mssd_error, 0, 1e-9);
  }
}

// A translation moves every vertex by its length, so ADD and MSSD both equal it: 3 mm is within
// 10% of the block's 54 mm diameter, 20 mm is not but is within the larger MSSD thresholds.
TEST_F(LocalizationServiceScoring, KnownOffsetsGiveTheirErrorsAndAMissBeyondTheThreshold) {
  const std::vector<Pose3> blocks = ThreeBlocks();
  const double offsets[] = {0, 0.003, 0.020};
  const Eigen::Vector3d directions[] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX(),
                                        Eigen::Vector3d(0, 3, 4) / 5};
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  for (size_t i = 0; i < 3; ++i) {
    plan.truth.push_back({0, blocks[i], 1.0});
    Pose3 estimate = blocks[i];
    estimate.translation() += offsets[i] * directions[i];
    plan.estimates.push_back({0, estimate, 1.0});
  }
  const auto score = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  const localization::PartScore& part = score->parts[0];
  const double diameter = Diameter(*LoadPart(FixturePart::kAngleBlock));
  ASSERT_GT(offsets[2], 0.1 * diameter);
  ASSERT_LT(offsets[1], 0.1 * diameter);

  EXPECT_EQ(part.add_correct, 2u);
  EXPECT_NEAR(*part.add_recall, 2.0 / 3, 1e-12);
  ASSERT_EQ(part.instances.size(), 3u);
  EXPECT_EQ(part.instances[0].estimate_index, 0u);
  EXPECT_EQ(part.instances[1].estimate_index, 1u);
  EXPECT_FALSE(part.instances[2].estimate_index.has_value());
  EXPECT_NEAR(part.instances[1].add_error, offsets[1], 1e-6);
  EXPECT_NEAR(part.instances[1].mssd_error, offsets[1], 1e-6);

  // Recall at each MSSD threshold: the share of the three offsets below it.
  ASSERT_EQ(part.mssd_recalls.size(), 10u);
  double sum = 0;
  for (size_t k = 0; k < 10; ++k) {
    const double threshold = 0.05 * static_cast<double>(k + 1) * diameter;
    const auto below = std::count_if(std::begin(offsets), std::end(offsets), [&](double e) { return e < threshold; });
    EXPECT_NEAR(part.mssd_recalls[k], static_cast<double>(below) / 3, 1e-12) << "threshold " << k;
    sum += static_cast<double>(below) / 3;
  }
  EXPECT_NEAR(*part.mssd_average_recall, sum / 10, 1e-12);
  EXPECT_NEAR(*score->mssd_average_recall, sum / 10, 1e-12);
}

// The tube flipped end for end and turned 50 degrees about its axis lies where it lay: correct
// under ADD-S and MSSD over its symmetries, far off under ADD, by the errors computed here.
TEST_F(LocalizationServiceScoring, ATubeTurnedOntoItselfIsRightOnlyUpToItsSymmetries) {
  const localization::PartSymmetries symmetries = SymmetriesOf(FixturePart::kRound);
  const Pose3 onto_itself = symmetries.discrete.at(0) * Turned(50 * std::numbers::pi / 180, Eigen::Vector3d::UnitZ(),
                                                                Eigen::Vector3d::Zero());
  const Pose3 truth = Turned(0.7, Eigen::Vector3d(1, 2, 3), {0.1, -0.2, 0.05});
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kRound), 1, symmetries});
  plan.parts.push_back({id(FixturePart::kRound), 1, std::nullopt});
  for (uint32_t part = 0; part < 2; ++part) {
    plan.truth.push_back({part, truth, 1.0});
    plan.estimates.push_back({part, truth * onto_itself, 1.0});
  }
  const auto score = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(score.ok()) << score.status().ToString();

  const TriangleMesh& tube = *LoadPart(FixturePart::kRound);
  const double diameter = Diameter(tube);
  double radius = 0;
  double mean_shift = 0;
  double largest_shift = 0;
  for (const Eigen::Vector3f& v : tube.vertices) {
    const double shift = (onto_itself * v.cast<double>() - v.cast<double>()).norm();
    mean_shift += shift / static_cast<double>(tube.vertices.size());
    largest_shift = std::max(largest_shift, shift);
    radius = std::max(radius, std::hypot(static_cast<double>(v.x()), static_cast<double>(v.y())));
  }

  const localization::PartScore& symmetric = score->parts[0];
  EXPECT_TRUE(symmetric.uses_add_s);
  EXPECT_EQ(symmetric.add_correct, 1u);
  // Its vertices lie on rings: a turned vertex is at most half a ring segment from the nearest one.
  EXPECT_LT(symmetric.instances[0].add_error, 0.002 * diameter);
  // The nearest of the 315 sampled turns is within half a step of 50 degrees, which moves the
  // outermost vertex by at most its radius times pi / 315.
  EXPECT_LT(symmetric.instances[0].mssd_error, radius * std::numbers::pi / 315);
  EXPECT_EQ(*symmetric.mssd_average_recall, 1.0);

  const localization::PartScore& plain = score->parts[1];
  EXPECT_FALSE(plain.uses_add_s);
  EXPECT_EQ(plain.add_correct, 0u);
  EXPECT_GT(mean_shift, 0.1 * diameter);
  EXPECT_FALSE(plain.instances[0].estimate_index.has_value());
  EXPECT_EQ(*plain.mssd_average_recall, 0.0);
  EXPECT_EQ(*score->add_recall, 0.5);

  // With every estimate kept matched, the plain part's errors show: the mean and largest shifts.
  plan.options.add_threshold = 10;
  plan.options.mssd_thresholds = {10};
  const auto loose = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(loose.ok()) << loose.status().ToString();
  EXPECT_NEAR(loose->parts[1].instances[0].add_error, mean_shift, 1e-6);
  EXPECT_NEAR(loose->parts[1].instances[0].mssd_error, largest_shift, 1e-6);
}

TEST_F(LocalizationServiceScoring, AScaleShrinksThePart) {
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  plan.parts.push_back({id(FixturePart::kAngleBlock), 0.5, std::nullopt});
  const auto score = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  const double diameter = Diameter(*LoadPart(FixturePart::kAngleBlock));
  EXPECT_NEAR(score->parts[0].diameter, diameter, 1e-9);
  EXPECT_NEAR(score->parts[1].diameter, diameter / 2, 1e-6);
  EXPECT_FALSE(score->add_recall.has_value());
}

// No estimate is an answer, not an error: every valid instance is missed.
TEST_F(LocalizationServiceScoring, AnEmptyEstimateListMissesEveryInstance) {
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  for (const Pose3& pose : ThreeBlocks()) plan.truth.push_back({0, pose, 1.0});
  const auto score = ScorePoses(world_.context().registry, plan);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  EXPECT_EQ(score->valid_instances, 3u);
  EXPECT_EQ(*score->add_recall, 0.0);
  EXPECT_EQ(*score->mssd_average_recall, 0.0);
  for (const auto& instance : score->parts[0].instances) EXPECT_FALSE(instance.estimate_index.has_value());
}

void ExpectRefused(const StatusOr<localization::ScanScore>& score, StatusCode code, const std::string& field) {
  EXPECT_EQ(score.status().code(), code) << score.status().ToString();
  EXPECT_TRUE(score.status().message().starts_with(field + ":")) << score.status().message();
}

TEST_F(LocalizationServiceScoring, RefusesBadPosesUnknownPartsAndUnknownMeshes) {
  ScoringPlan good;
  good.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  good.truth.push_back({0, Pose3::Identity(), 1.0});
  good.estimates.push_back({0, Pose3::Identity(), 1.0});
  ASSERT_TRUE(ScorePoses(world_.context().registry, good).ok());
  const double nan = std::numeric_limits<double>::quiet_NaN();

  ScoringPlan plan = good;
  plan.estimates[0].world_from_part.translation().y() = nan;
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kInvalidArgument, "estimates[0].world_from_part");

  plan = good;
  plan.truth[0].world_from_part.linear()(1, 2) = nan;
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kInvalidArgument, "truth[0].world_from_part");

  plan = good;
  plan.estimates[0].score = nan;
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kInvalidArgument, "estimates[0].score");

  plan = good;
  plan.estimates.push_back({1, Pose3::Identity(), 1.0});
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kInvalidArgument, "estimates[1].part_id");

  plan = good;
  plan.truth[0].part_id = 7;
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kInvalidArgument, "truth[0].part_id");

  plan = good;
  plan.parts.push_back({"msh_0000000000000000", 1, std::nullopt});
  ExpectRefused(ScorePoses(world_.context().registry, plan), StatusCode::kNotFound, "parts[1].mesh_id");
}

// 200 x 200 poses of a part with a symmetry axis: each pair places every vertex for each of 315
// sampled turns, far past the bound. Refused before any scoring, naming the estimates.
TEST_F(LocalizationServiceScoring, RequestsPastTheWorkBoundAreRefusedUpFront) {
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kRound), 1, SymmetriesOf(FixturePart::kRound)});
  for (int i = 0; i < 200; ++i) {
    const Pose3 pose = Turned(0.1 * i, Eigen::Vector3d(1, 2, 3), {0.2 * i, 0, 0});
    plan.truth.push_back({0, pose, 1.0});
    plan.estimates.push_back({0, pose, 1.0});
  }
  const auto refused = ScorePoses(world_.context().registry, plan);
  ASSERT_EQ(refused.status().code(), StatusCode::kResourceExhausted) << refused.status().ToString();
  EXPECT_NE(refused.status().message().find("estimates"), std::string::npos) << refused.status().message();
  // Truths the scan barely sees are not scored, so they cost nothing.
  for (auto& truth : plan.truth) truth.visible_fraction = 0.0;
  plan.truth[0].visible_fraction = 1.0;
  plan.estimates.resize(2);
  EXPECT_TRUE(ScorePoses(world_.context().registry, plan).ok());
}

TEST_F(LocalizationServiceScoring, ACancelledCallEndsCancelled) {
  ScoringPlan plan;
  plan.parts.push_back({id(FixturePart::kAngleBlock), 1, std::nullopt});
  for (const Pose3& pose : ThreeBlocks()) {
    plan.truth.push_back({0, pose, 1.0});
    plan.estimates.push_back({0, pose, 0.5});
  }
  const std::atomic<bool> cancel{true};
  EXPECT_EQ(ScorePoses(world_.context().registry, plan, &cancel).status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::service
