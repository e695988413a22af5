#include "localization/bop_scoring.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "localization/pose_matching.h"
#include "part_shapes.h"

namespace vscan::localization {
namespace {

using testing::CubeRotations;
using testing::CubeWithFaceCentres;

// A cube's vertices with one more above a corner: no symmetry left.
PartDefinition Asymmetric(uint32_t id) {
  PartDefinition part;
  part.part_id = id;
  part.vertices = CubeWithFaceCentres(0.05);
  part.vertices.emplace_back(0.05f, 0.05f, 0.1f);
  return part;
}

double AsymmetricDiameter() {
  // From (-h, -h, -h) to (h, h, 2h) with h = 0.05.
  return std::sqrt(0.1 * 0.1 + 0.1 * 0.1 + 0.15 * 0.15);
}

Pose3 At(double x, double y) {
  Pose3 pose = RotationAboutLine(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.3, 1, 0.2), 0.5);
  pose.translation() = Eigen::Vector3d(x, y, 0.02);
  return pose;
}

Pose3 Shifted(const Pose3& pose, double d) {
  Pose3 out = pose;
  out.translation().x() += d;
  return out;
}

TEST(ScoreScan, ExactEstimatesGiveRecallOne) {
  const std::vector<PartDefinition> parts{Asymmetric(7)};
  const std::vector<TrueInstance> truth{{7, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{7, At(0, 0), 0.5}};
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  ASSERT_EQ(score->parts.size(), 1u);
  const PartScore& part = score->parts[0];
  EXPECT_NEAR(part.diameter, AsymmetricDiameter(), 1e-7);
  EXPECT_FALSE(part.uses_add_s);
  EXPECT_EQ(part.add_recall, 1.0);
  EXPECT_EQ(part.mssd_average_recall, 1.0);
  ASSERT_EQ(part.instances.size(), 1u);
  EXPECT_EQ(part.instances[0].estimate_index, 0u);
  EXPECT_NEAR(part.instances[0].add_error, 0, 1e-12);
  EXPECT_EQ(score->add_recall, 1.0);
  EXPECT_EQ(score->mssd_average_recall, 1.0);
}

TEST(ScoreScan, OffsetBetweenThresholdsCountsTheThresholdsAboveIt) {
  // 0.12 diameters: wrong for ADD (0.10), right for MSSD from 0.15 on: 8 of 10 thresholds.
  const std::vector<PartDefinition> parts{Asymmetric(1)};
  const double d = 0.12 * AsymmetricDiameter();
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{1, Shifted(At(0, 0), d), 1.0}};
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok());
  EXPECT_EQ(score->add_recall, 0.0);
  EXPECT_NEAR(*score->mssd_average_recall, 0.8, 1e-12);
  const std::vector<double> expected{0, 0, 1, 1, 1, 1, 1, 1, 1, 1};
  EXPECT_EQ(score->parts[0].mssd_recalls, expected);
}

TEST(ScoreScan, KnownDiameterSetsTheThresholds) {
  // 0.12 of the vertices' diameter is 0.06 of a known diameter twice as large: right for ADD, and
  // for MSSD from 0.1 on.
  PartDefinition part = Asymmetric(1);
  part.known_diameter = 2 * AsymmetricDiameter();
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{1, Shifted(At(0, 0), 0.12 * AsymmetricDiameter()), 1.0}};
  auto score = ScoreScan(std::vector<PartDefinition>{part}, truth, estimates);
  ASSERT_TRUE(score.ok()) << score.status().ToString();
  EXPECT_EQ(score->parts[0].diameter, part.known_diameter);
  EXPECT_EQ(score->add_recall, 1.0);
  EXPECT_EQ(score->parts[0].mssd_recalls, (std::vector<double>{0, 1, 1, 1, 1, 1, 1, 1, 1, 1}));
  for (const double bad : {-1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    part.known_diameter = bad;
    EXPECT_EQ(ScoreScan(std::vector<PartDefinition>{part}, truth, estimates).status().field(),
              "parts[0].known_diameter");
  }
}

TEST(ScoreScan, SymmetricPartIsScoredWithAddS) {
  PartDefinition cube;
  cube.part_id = 3;
  cube.vertices = CubeWithFaceCentres(0.05);
  cube.symmetries.discrete = CubeRotations();
  const Pose3 truth_pose = At(0.2, 0.1);
  const Pose3 turned = truth_pose * CubeRotations()[5];
  const std::vector<TrueInstance> truth{{3, truth_pose, 1.0}};
  const std::vector<EstimatedInstance> estimates{{3, turned, 1.0}};
  auto score = ScoreScan(std::vector<PartDefinition>{cube}, truth, estimates);
  ASSERT_TRUE(score.ok());
  EXPECT_TRUE(score->parts[0].uses_add_s);
  EXPECT_EQ(score->add_recall, 1.0);
  EXPECT_EQ(score->mssd_average_recall, 1.0);
}

TEST(ScoreScan, AddSRecallTakesBopsDirection) {
  // Vertices at 0, 1 and 5 cm on the x axis, symmetric about it; the estimate 4 cm along it. ADD-S
  // from the true vertices is 7/3 cm (from the estimated ones it would be 5/3 cm): above a threshold
  // of 0.4 diameters (2 cm), below one of 0.5 (2.5 cm).
  PartDefinition line;
  line.part_id = 4;
  line.vertices = {{0, 0, 0}, {0.01f, 0, 0}, {0.05f, 0, 0}};
  line.symmetries.continuous.push_back({Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero()});
  const std::vector<TrueInstance> truth{{4, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{4, At(0, 0) * Eigen::Translation3d(0.04, 0, 0), 1.0}};
  ScoringOptions options;
  options.add_threshold = 0.4;
  auto strict = ScoreScan(std::vector<PartDefinition>{line}, truth, estimates, options);
  ASSERT_TRUE(strict.ok()) << strict.status().ToString();
  EXPECT_TRUE(strict->parts[0].uses_add_s);
  EXPECT_EQ(strict->add_recall, 0.0);
  EXPECT_FALSE(strict->parts[0].instances[0].estimate_index.has_value());
  options.add_threshold = 0.5;
  auto loose = ScoreScan(std::vector<PartDefinition>{line}, truth, estimates, options);
  ASSERT_TRUE(loose.ok());
  EXPECT_EQ(loose->add_recall, 1.0);
  EXPECT_NEAR(loose->parts[0].instances[0].add_error, 0.07 / 3, 1e-8);
}

TEST(ScoreScan, ErrorsAreComparedAsFractionsOfTheDiameter) {
  // Dyadic lengths, so that every distance is exact: a part 25/256 m long moved by 35/1024 m along
  // itself has MSSD / diameter = 0.35 (the double nearest), below BOP's seventh threshold
  // 0.05 * 7 = 0.35000000000000003. Compared as MSSD < 0.35000000000000003 * diameter instead, the
  // product rounds down to the MSSD and the instance would be missed at that threshold.
  PartDefinition rod;
  rod.part_id = 2;
  const double length = 25.0 / 256, shift = 35.0 / 1024;
  rod.vertices = {{0, 0, 0}, {static_cast<float>(length), 0, 0}};
  const std::vector<TrueInstance> truth{{2, Pose3::Identity(), 1.0}};
  Pose3 moved = Pose3::Identity();
  moved.translation().x() = shift;
  const std::vector<EstimatedInstance> estimates{{2, moved, 1.0}};
  ASSERT_FALSE(shift < BopMssdThresholds()[6] * length);  // the rounding this is about
  auto score = ScoreScan(std::vector<PartDefinition>{rod}, truth, estimates);
  ASSERT_TRUE(score.ok());
  EXPECT_EQ(score->parts[0].diameter, length);
  const std::vector<double> expected{0, 0, 0, 0, 0, 0, 1, 1, 1, 1};
  EXPECT_EQ(score->parts[0].mssd_recalls, expected);
}

TEST(ScoreScan, MssdThresholdsAreTheDoublesOfBopsArange) {
  // np.arange(0.05, 0.51, 0.05) is 0.05 + 0.05 i; its sixth value is 0.3 (0.05 * 6 is
  // 0.30000000000000004).
  const std::vector<double> thresholds = BopMssdThresholds();
  ASSERT_EQ(thresholds.size(), 10u);
  for (size_t i = 0; i < thresholds.size(); ++i) EXPECT_EQ(thresholds[i], 0.05 + 0.05 * static_cast<double>(i));
  EXPECT_EQ(thresholds[5], 0.3);
  // A rod 5/64 m long moved by 3/128 m along itself: MSSD / diameter is the double 0.3, not below
  // that threshold; correct from 0.35 on.
  PartDefinition rod;
  rod.part_id = 5;
  const double length = 5.0 / 64, shift = 3.0 / 128;
  rod.vertices = {{0, 0, 0}, {static_cast<float>(length), 0, 0}};
  Pose3 moved = Pose3::Identity();
  moved.translation().x() = shift;
  auto score = ScoreScan(std::vector<PartDefinition>{rod}, std::vector<TrueInstance>{{5, Pose3::Identity(), 1.0}},
                         std::vector<EstimatedInstance>{{5, moved, 1.0}});
  ASSERT_TRUE(score.ok());
  const std::vector<double> expected{0, 0, 0, 0, 0, 0, 1, 1, 1, 1};
  EXPECT_EQ(score->parts[0].mssd_recalls, expected);
}

TEST(ScoreScan, SwappedEstimatesMatchTheirNearestInstances) {
  const std::vector<PartDefinition> parts{Asymmetric(1)};
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}, {1, At(0.5, 0), 1.0}};
  // Listed in the other order, the better-scored one off by 2 mm.
  const std::vector<EstimatedInstance> estimates{{1, Shifted(At(0.5, 0), 0.002), 0.9}, {1, At(0, 0), 0.8}};
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok());
  const PartScore& part = score->parts[0];
  ASSERT_EQ(part.instances.size(), 2u);
  EXPECT_EQ(part.instances[0].true_index, 0u);
  EXPECT_EQ(part.instances[0].estimate_index, 1u);
  EXPECT_NEAR(part.instances[0].add_error, 0, 1e-12);
  EXPECT_EQ(part.instances[1].estimate_index, 0u);
  EXPECT_NEAR(part.instances[1].add_error, 0.002, 1e-9);
  EXPECT_EQ(score->add_recall, 1.0);
}

TEST(ScoreScan, EstimateOfAPartWithoutTruthChangesNoRecall) {
  const std::vector<PartDefinition> parts{Asymmetric(1), Asymmetric(2)};
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{2, At(0, 0), 0.99}, {1, At(0, 0), 0.5}};
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok());
  EXPECT_EQ(score->valid_instances, 1u);
  EXPECT_EQ(score->add_recall, 1.0);
  ASSERT_EQ(score->parts.size(), 2u);
  EXPECT_EQ(score->parts[1].valid_instances, 0u);
  EXPECT_EQ(score->parts[1].estimates, 1u);
  EXPECT_FALSE(score->parts[1].add_recall.has_value());
  EXPECT_FALSE(score->parts[1].mssd_average_recall.has_value());
}

TEST(ScoreScan, BarelyVisibleInstanceIsNotCounted) {
  const std::vector<PartDefinition> parts{Asymmetric(1)};
  const std::vector<TrueInstance> truth{{1, At(0, 0), 0.6}, {1, At(0.5, 0), 0.05}};
  // The estimate of the hidden instance is better scored; it must not be matched at all.
  const std::vector<EstimatedInstance> estimates{{1, At(0.5, 0), 0.9}, {1, At(0, 0), 0.3}};
  ScoringOptions options;
  options.keep_top_estimates = false;
  auto score = ScoreScan(parts, truth, estimates, options);
  ASSERT_TRUE(score.ok());
  EXPECT_EQ(score->valid_instances, 1u);
  EXPECT_EQ(score->add_recall, 1.0);
  ASSERT_EQ(score->parts[0].instances.size(), 1u);
  EXPECT_EQ(score->parts[0].instances[0].estimate_index, 1u);
  // With no estimate of the seen one, recall drops to 0: the hidden one cannot stand in.
  auto missed = ScoreScan(parts, truth, std::vector<EstimatedInstance>{{1, At(0.5, 0), 0.9}}, options);
  ASSERT_TRUE(missed.ok());
  EXPECT_EQ(missed->add_recall, 0.0);
}

TEST(ScoreScan, OnlyTheTopEstimatesPerInstanceCount) {
  const std::vector<PartDefinition> parts{Asymmetric(1)};
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{1, At(0.3, 0), 0.9}, {1, At(0, 0), 0.5}};
  auto top = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(top.ok());
  EXPECT_EQ(top->add_recall, 0.0);
  ScoringOptions all;
  all.keep_top_estimates = false;
  auto every = ScoreScan(parts, truth, estimates, all);
  ASSERT_TRUE(every.ok());
  EXPECT_EQ(every->add_recall, 1.0);
}

TEST(ScoreScan, RecallIsPooledOverParts) {
  const std::vector<PartDefinition> parts{Asymmetric(1), Asymmetric(2)};
  const std::vector<TrueInstance> truth{{1, At(0, 0), 1.0}, {2, At(0.5, 0), 1.0}, {2, At(1, 0), 1.0}};
  const std::vector<EstimatedInstance> estimates{{2, At(0.5, 0), 1.0}};
  auto score = ScoreScan(parts, truth, estimates);
  ASSERT_TRUE(score.ok());
  EXPECT_NEAR(*score->add_recall, 1.0 / 3, 1e-12);
  EXPECT_EQ(score->parts[0].add_recall, 0.0);
  EXPECT_EQ(score->parts[1].add_recall, 0.5);
}

TEST(ScoreScan, RejectsUnknownPartsAndBadValues) {
  const std::vector<PartDefinition> parts{Asymmetric(1)};
  auto unknown = ScoreScan(parts, std::vector<TrueInstance>{{4, At(0, 0), 1.0}}, {});
  EXPECT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(unknown.status().field(), "truth[0].part_id");
  auto score = ScoreScan(parts, {}, std::vector<EstimatedInstance>{{1, At(0, 0), std::nan("")}});
  EXPECT_EQ(score.status().field(), "estimates[0].score");
  auto visible = ScoreScan(parts, std::vector<TrueInstance>{{1, At(0, 0), 1.5}}, {});
  EXPECT_EQ(visible.status().field(), "truth[0].visible_fraction");
  auto twice = ScoreScan(std::vector<PartDefinition>{Asymmetric(1), Asymmetric(1)}, {}, {});
  EXPECT_EQ(twice.status().field(), "parts[1].part_id");
}

TEST(MatchEstimates, BestScoredTakesItsLowestErrorFirst) {
  // Estimate 1 is scored higher and takes instance 1 (0.2 < 0.3); estimate 0 is left instance 0.
  Eigen::MatrixXd errors(2, 2);
  errors << 0.1, 0.5,  //
      0.3, 0.2;
  const std::vector<double> scores{0.4, 0.9};
  const bool valid[] = {true, true};
  EXPECT_EQ(MatchEstimates(scores, errors, valid, 0.35, 0), (std::vector<int>{0, 1}));
  // Greedy, not optimal: estimate 1 takes instance 0 now, and estimate 0 is too far from instance 1.
  errors << 0.1, 0.5,  //
      0.05, 0.2;
  EXPECT_EQ(MatchEstimates(scores, errors, valid, 0.35, 0), (std::vector<int>{1, kUnmatched}));
  // Only the top estimate: instance 0 alone.
  EXPECT_EQ(MatchEstimates(scores, errors, valid, 0.35, 1), (std::vector<int>{1, kUnmatched}));
  // An error equal to the threshold is not below it.
  EXPECT_EQ(MatchEstimates(scores, errors, valid, 0.05, 0), (std::vector<int>{kUnmatched, kUnmatched}));
}

}  // namespace
}  // namespace vscan::localization
