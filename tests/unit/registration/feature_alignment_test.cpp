#include "registration/feature_alignment.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "evaluation/surface_sampling.h"
#include "icp_test_util.h"
#include "machined_parts.h"
#include "reference_pair.h"
#include "registration/descriptor_matching.h"
#include "registration/feature_cloud.h"
#include "registration/match_consensus.h"
#include "registration/normal_orientation.h"
#include "spatial/kd_tree.h"
#include "synthetic_shapes.h"

namespace vscan::registration {
namespace {

using testing::Cloud;
using testing::Motion;
using testing::RotationErrorDeg;
using testing::TranslationErrorMm;

std::vector<Eigen::Vector3f> MovedPoints(std::span<const Eigen::Vector3f> points, const Pose3& pose) {
  std::vector<Eigen::Vector3f> moved;
  moved.reserve(points.size());
  for (const auto& p : points) moved.push_back((pose * p.cast<double>()).cast<float>());
  return moved;
}

// The reference pair thinned as AlignByFeatures thins it, so that the tests copy and move less.
struct ThinPair {
  std::vector<Eigen::Vector3f> source;
  std::vector<Eigen::Vector3f> target;
  Pose3 target_from_source;
};

const ThinPair& ThinReferencePair() {
  static const ThinPair pair = [] {
    const auto& reference = testing::LoadReferencePair();
    const double voxel = FeatureAlignmentOptions{}.voxel_size;
    return ThinPair{ThinToVoxels(reference.source.points, voxel), ThinToVoxels(reference.target.points, voxel),
                    reference.target_from_source};
  }();
  return pair;
}

// The source moved by `motion`, so that target_from_source becomes truth * motion^-1.
struct MovedCase {
  std::vector<Eigen::Vector3f> source;
  Pose3 truth;
};

MovedCase MoveSource(std::span<const Eigen::Vector3f> source, const Pose3& target_from_source, const Pose3& motion) {
  return {MovedPoints(source, motion), target_from_source * motion.inverse()};
}

void ExpectFoundNear(const StatusOr<FeatureAlignmentResult>& result, const Pose3& truth, const std::string& what) {
  ASSERT_TRUE(result.ok()) << what << ": " << result.status().ToString();
  ASSERT_TRUE(result->found) << what << ": " << result->reason;
  // ICP on the thinned clouds ends near the data's floor (about 0.005 deg on the reference pair).
  EXPECT_LT(RotationErrorDeg(result->target_from_source, truth), 0.05) << what;
  EXPECT_LT(TranslationErrorMm(result->target_from_source, truth), 0.5) << what;
  EXPECT_GE(result->inliers, FeatureAlignmentOptions{}.min_inliers) << what;
  EXPECT_LE(result->inliers, result->matches) << what;
  EXPECT_TRUE(result->reason.empty()) << what;
}

// The reference pair with the source turned by angle_deg about a tilted axis and moved 5 cm.
void ExpectFoundWhenTurned(double angle_deg) {
  const ThinPair& pair = ThinReferencePair();
  const MovedCase moved =
      MoveSource(pair.source, pair.target_from_source, Motion(angle_deg, {0.4, -0.3, 0.85}, {0.05, 0.0, 0.0}));
  // Far beyond where ICP alone converges.
  ASSERT_GT(RotationErrorDeg(Pose3::Identity(), moved.truth), angle_deg - 5.0);
  const auto result = AlignByFeatures(moved.source, pair.target, FeatureAlignmentOptions{});
  ExpectFoundNear(result, moved.truth, std::to_string(angle_deg) + " deg");
  if (result.ok()) {
    // Two independent draws of one surface: nearly every point has a partner within 2 voxels.
    EXPECT_GT(result->fitness, 0.9);
  }
}

TEST(FeatureAlignmentTest, FindsTheReferencePairTurnedBy60Degrees) { ExpectFoundWhenTurned(60.0); }

TEST(FeatureAlignmentTest, FindsTheReferencePairTurnedBy150Degrees) { ExpectFoundWhenTurned(150.0); }

TEST(FeatureAlignmentTest, FindsTwoHalvesThatOverlapByHalf) {
  const ThinPair& pair = ThinReferencePair();
  // Cut along x in the target frame at the thirds: each part keeps two thirds of the object, half
  // of it shared with the other part.
  const std::vector<Eigen::Vector3f> source_in_target = MovedPoints(pair.source, pair.target_from_source);
  std::vector<float> xs;
  for (const auto& p : pair.target) xs.push_back(p.x());
  std::sort(xs.begin(), xs.end());
  const float low = xs[xs.size() / 3], high = xs[2 * xs.size() / 3];
  std::vector<Eigen::Vector3f> target_part, source_part;
  size_t shared = 0;
  for (const auto& p : pair.target) {
    if (p.x() < high) target_part.push_back(p);
  }
  for (size_t i = 0; i < pair.source.size(); ++i) {
    if (source_in_target[i].x() <= low) continue;
    source_part.push_back(pair.source[i]);
    shared += source_in_target[i].x() < high ? 1 : 0;
  }
  const double overlap = static_cast<double>(shared) / static_cast<double>(source_part.size());
  ASSERT_GT(overlap, 0.4);
  ASSERT_LT(overlap, 0.6);

  const MovedCase moved =
      MoveSource(source_part, pair.target_from_source, Motion(120.0, {-0.2, 1.0, 0.3}, {0.0, 0.05, -0.03}));
  const auto result = AlignByFeatures(moved.source, target_part, FeatureAlignmentOptions{});
  ExpectFoundNear(result, moved.truth, "halves");
  if (result.ok()) {
    // The points outside the shared band have nothing to match.
    EXPECT_GT(result->fitness, overlap - 0.1);
    EXPECT_LT(result->fitness, overlap + 0.1);
  }
}

void ExpectNotFound(const StatusOr<FeatureAlignmentResult>& result, const std::string& reason_part,
                    const std::string& what) {
  ASSERT_TRUE(result.ok()) << what << ": " << result.status().ToString();
  EXPECT_FALSE(result->found) << what;
  EXPECT_FALSE(result->reason.empty()) << what;
  EXPECT_NE(result->reason.find(reason_part), std::string::npos) << what << ": " << result->reason;
  EXPECT_TRUE(result->target_from_source.isApprox(Pose3::Identity())) << what << ": a failure must not carry a pose";
}

TEST(FeatureAlignmentTest, APlaneDoesNotAlignWithTheObject) {
  // 40 x 40 cm, larger than any face of the object, sampled every 3 mm with 0.5 mm noise.
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.0005f);
  std::vector<Eigen::Vector3f> plane;
  for (int i = 0; i < 133; ++i) {
    for (int j = 0; j < 133; ++j)
      plane.emplace_back(0.003f * static_cast<float>(i) - 0.2f, 0.003f * static_cast<float>(j) - 0.2f, noise(rng));
  }
  const auto result = AlignByFeatures(plane, ThinReferencePair().target, FeatureAlignmentOptions{});
  ExpectNotFound(result, "", "plane");
}

TEST(FeatureAlignmentTest, RandomCloudsDoNotAlign) {
  std::mt19937 rng(5);
  // Points filling a 10 cm cube: no surface, so any pose fits them equally well.
  std::uniform_real_distribution<float> u(-0.05f, 0.05f);
  std::vector<Eigen::Vector3f> a, b;
  for (int i = 0; i < 8000; ++i) a.emplace_back(u(rng), u(rng), u(rng));
  for (int i = 0; i < 8000; ++i) b.emplace_back(u(rng), u(rng), u(rng));
  const auto result = AlignByFeatures(a, b, FeatureAlignmentOptions{});
  ExpectNotFound(result, "", "random");
}

TEST(FeatureAlignmentTest, TooFewPointsIsReportedNotAnError) {
  const ThinPair& pair = ThinReferencePair();
  const std::vector<Eigen::Vector3f> few(pair.source.begin(), pair.source.begin() + 50);
  ExpectNotFound(AlignByFeatures(few, pair.target, FeatureAlignmentOptions{}), "too few points: the source",
                 "few source points");
  ExpectNotFound(AlignByFeatures(pair.source, few, FeatureAlignmentOptions{}), "too few points: the target",
                 "few target points");
  ExpectNotFound(AlignByFeatures({}, pair.target, FeatureAlignmentOptions{}), "too few points", "empty source");
}

TEST(FeatureAlignmentTest, AConsensusSmallerThanMinInliersIsNone) {
  const ThinPair& pair = ThinReferencePair();
  FeatureAlignmentOptions options;
  options.voxel_size = 0.005;  // fewer points, the same path
  options.min_inliers = 300;
  const auto result = AlignByFeatures(pair.source, pair.target, options);
  ExpectNotFound(result, "no consensus", "min_inliers 300");
  // There were enough matches, just not that many that agree.
  EXPECT_GE(result->matches, options.min_inliers);
  EXPECT_GT(result->inliers, 12u);
  EXPECT_LT(result->inliers, options.min_inliers);
}

TEST(FeatureAlignmentTest, TheSameSeedGivesTheSameTransformWhateverTheThreads) {
  const ThinPair& pair = ThinReferencePair();
  const MovedCase moved =
      MoveSource(pair.source, pair.target_from_source, Motion(60.0, {0.4, -0.3, 0.85}, {0.05, 0.0, 0.0}));
  FeatureAlignmentOptions options;
  options.voxel_size = 0.005;  // fewer points, the same path
  const auto first = AlignByFeatures(moved.source, pair.target, options);
  std::optional<StatusOr<FeatureAlignmentResult>> second;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { second.emplace(AlignByFeatures(moved.source, pair.target, options)); });
  ASSERT_TRUE(first.ok() && second->ok());
  ASSERT_TRUE(first->found && (*second)->found);
  EXPECT_EQ(first->target_from_source.matrix(), (*second)->target_from_source.matrix());
  EXPECT_EQ(first->inliers, (*second)->inliers);
  EXPECT_EQ(first->matches, (*second)->matches);

  options.seed = 99;
  const auto third = AlignByFeatures(moved.source, pair.target, options);
  ExpectFoundNear(third, moved.truth, "seed 99");
  // The seed only changes which hypotheses are drawn; refined by ICP they land on the same answer.
  EXPECT_LT(RotationErrorDeg(third->target_from_source, first->target_from_source), 0.05);
}

TEST(FeatureAlignmentTest, OptionsOutOfRangeNameTheirField) {
  const ThinPair& pair = ThinReferencePair();
  const auto expect_invalid = [&](const FeatureAlignmentOptions& options, const std::string& field) {
    const auto result = AlignByFeatures(pair.source, pair.target, options);
    ASSERT_FALSE(result.ok()) << field;
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument) << field;
    EXPECT_EQ(result.status().field(), field);
  };
  FeatureAlignmentOptions o;
  o.voxel_size = 0.0;
  expect_invalid(o, "features.voxel_size");
  o = {};
  o.voxel_size = std::numeric_limits<double>::quiet_NaN();
  expect_invalid(o, "features.voxel_size");
  o = {};
  o.normal_radius_voxels = 0.5;
  expect_invalid(o, "features.normal_radius_voxels");
  o = {};
  o.descriptor_radius_voxels = 2.0;  // smaller than the normals' radius
  expect_invalid(o, "features.descriptor_radius_voxels");
  o = {};
  o.keypoint_spacing_voxels = 0.5;
  expect_invalid(o, "features.keypoint_spacing_voxels");
  o = {};
  o.ransac_iterations = 0;
  expect_invalid(o, "features.ransac_iterations");
  o = {};
  o.inlier_distance_voxels = -1.0;
  expect_invalid(o, "features.inlier_distance_voxels");
  o = {};
  o.min_inliers = 2;
  expect_invalid(o, "features.min_inliers");
  o = {};
  o.min_fitness = 1.5;
  expect_invalid(o, "features.min_fitness");
}

TEST(FeatureAlignmentTest, CancelStopsTheWork) {
  const ThinPair& pair = ThinReferencePair();
  const std::atomic<bool> cancel = true;
  const auto result = AlignByFeatures(pair.source, pair.target, FeatureAlignmentOptions{}, &cancel);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kCancelled);
}

// The share of the prepared cloud's normals (away from edges, where the true normal is ambiguous)
// that face the same way as the true normal of the nearest input point, moved by `pose`.
double ShareFacingLikeTruth(const FeatureCloud& prepared, const Cloud& truth, const Pose3& pose) {
  const spatial::KdTree tree(truth.points);
  size_t clear = 0, agree = 0;
  for (size_t i = 0; i < prepared.points.size(); ++i) {
    const Eigen::Vector3f p = (pose.inverse() * prepared.points[i].cast<double>()).cast<float>();
    const Eigen::Vector3f n = (pose.linear().transpose() * prepared.normals[i].cast<double>()).cast<float>();
    spatial::Neighbor nearest{};
    tree.Knn(p, std::numeric_limits<float>::infinity(), std::span(&nearest, 1));
    const float cosine = n.dot(truth.normals[tree.original_index(nearest.slot)]);
    if (std::abs(cosine) < 0.9f) continue;
    ++clear;
    agree += cosine > 0.0f ? 1 : 0;
  }
  EXPECT_GT(clear, prepared.points.size() / 2);
  return static_cast<double>(agree) / static_cast<double>(clear);
}

TEST(NormalOrientationTest, EstimatedNormalsFaceOutwardInAnyFrame) {
  const Cloud truth = testing::BoxAndSphere(60000, 7);
  const FeatureCloudOptions options{.voxel = 0.003, .normal_radius = 0.009, .keypoint_spacing = 0.009};
  for (const Pose3& pose : {Pose3::Identity(), Motion(130.0, {0.2, -1.0, 0.5}, {0.3, 0.1, -0.2})}) {
    const auto prepared = PrepareFeatureCloud(MovedPoints(truth.points, pose), options);
    ASSERT_TRUE(prepared.ok());
    EXPECT_EQ(ShareFacingLikeTruth(*prepared, truth, pose), 1.0);
  }
}

TEST(NormalOrientationTest, ExactNormalsWithRandomSignsBecomeOutward) {
  const Cloud truth = testing::BoxAndSphere(20000, 7);
  std::vector<Eigen::Vector3f> normals = truth.normals;
  std::mt19937 rng(8);
  for (auto& n : normals) n *= (rng() & 1) != 0 ? -1.0f : 1.0f;
  // The sphere alone: the box's sharp edges give no hint which way to cross them.
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3f> sphere_normals, sphere_truth;
  for (size_t i = 0; i < truth.points.size(); ++i) {
    if ((truth.points[i] - Eigen::Vector3f(0.17f, 0.02f, 0.03f)).norm() > 0.0501f) continue;
    points.push_back(truth.points[i]);
    sphere_normals.push_back(normals[i]);
    sphere_truth.push_back(truth.normals[i]);
  }
  ASSERT_GT(points.size(), 1000u);
  OrientNormalsConsistently(points, sphere_normals, 8, 0.01f);
  size_t outward = 0;
  for (size_t i = 0; i < points.size(); ++i) outward += sphere_normals[i].dot(sphere_truth[i]) > 0.0f ? 1 : 0;
  EXPECT_EQ(outward, points.size());
}

// The share of a view's prepared normals that face its sensor (at the origin of the sensor frame).
double ShareFacingSensor(const FeatureCloud& prepared, const Eigen::Vector3f& sensor) {
  size_t facing = 0;
  for (size_t i = 0; i < prepared.points.size(); ++i) {
    facing += prepared.normals[i].dot(sensor - prepared.points[i]) > 0.0f ? 1 : 0;
  }
  return static_cast<double>(facing) / static_cast<double>(prepared.points.size());
}

// Two views of the bracket 30 degrees apart whose normals, oriented by shape alone, come out on
// opposite sides of the surface: one view is mostly the concave corner of plate and riser, the
// other mostly convex edges.
struct BracketViews {
  testing::MachinedPart part = testing::MakeMachinedPart(0);
  Pose3 world_from_a = testing::ViewOfPart(-70.0, 35.0, 0.35);
  Pose3 world_from_b = testing::ViewOfPart(-40.0, 35.0, 0.35);
  testing::PartCamera camera{.width = 320, .height = 240, .fov_deg = 60.0};
  std::vector<Eigen::Vector3f> a = testing::ScanPart(part, world_from_a, 0.0002, 1, camera);
  std::vector<Eigen::Vector3f> b = testing::ScanPart(part, world_from_b, 0.0002, 2, camera);
};

TEST(NormalOrientationTest, SensorOrientedNormalsFaceTheSensor) {
  const BracketViews views;
  for (const Pose3& pose : {Pose3::Identity(), Motion(130.0, {0.2, -1.0, 0.5}, {0.3, 0.1, -0.2})}) {
    const Eigen::Vector3f sensor = pose.translation().cast<float>();
    FeatureCloudOptions options{.voxel = 0.002, .normal_radius = 0.006, .keypoint_spacing = 0.006};
    options.viewpoint = sensor;
    const auto prepared = PrepareFeatureCloud(MovedPoints(views.a, pose), options);
    ASSERT_TRUE(prepared.ok());
    ASSERT_GT(prepared->points.size(), 1000u);
    EXPECT_EQ(ShareFacingSensor(*prepared, sensor), 1.0);
  }
}

TEST(FeatureAlignmentTest, FlatFacedViewsWhoseShapeSignsDisagreeAlign) {
  const BracketViews views;
  const Pose3 truth = views.world_from_b.inverse() * views.world_from_a;  // b_from_a
  const FeatureCloudOptions prepare{.voxel = 0.002, .normal_radius = 0.006, .keypoint_spacing = 0.006};
  const auto a = PrepareFeatureCloud(views.a, prepare);
  const auto b = PrepareFeatureCloud(views.b, prepare);
  ASSERT_TRUE(a.ok() && b.ok());
  // The case this guards: without a viewpoint the two views' signs disagree.
  const double a_facing = ShareFacingSensor(*a, Eigen::Vector3f::Zero());
  const double b_facing = ShareFacingSensor(*b, Eigen::Vector3f::Zero());
  ASSERT_TRUE((a_facing > 0.9 && b_facing < 0.1) || (a_facing < 0.1 && b_facing > 0.9)) << a_facing << " " << b_facing;

  FeatureAlignmentOptions options;
  options.voxel_size = 0.002;
  for (const bool viewpoints : {false, true}) {
    if (viewpoints) {
      options.source_viewpoint = Eigen::Vector3f::Zero();
      options.target_viewpoint = Eigen::Vector3f::Zero();
    }
    const auto result = AlignByFeatures(views.a, views.b, options);
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    ASSERT_TRUE(result->found) << result->reason << (viewpoints ? " (viewpoints)" : " (no viewpoints)");
    EXPECT_LT(RotationErrorDeg(result->target_from_source, truth), 0.2) << viewpoints;
    EXPECT_LT(TranslationErrorMm(result->target_from_source, truth), 1.0) << viewpoints;
    EXPECT_EQ(result->flipped_normals, !viewpoints);
  }
}

TEST(FeatureAlignmentTest, AUnionOfViewsLaysOntoItsMeshWithSignsFromSensorsAndFaces) {
  const testing::MachinedPart part = testing::MakeMachinedPart(0);
  std::vector<Eigen::Vector3f> union_points, towards_sensor;
  for (const double azimuth : {-60.0, 20.0, 100.0, 180.0}) {
    const Pose3 world_from_sensor = testing::ViewOfPart(azimuth, 40.0, 0.35);
    const Eigen::Vector3f origin = world_from_sensor.translation().cast<float>();
    for (const Eigen::Vector3f& p : testing::ScanPart(part, world_from_sensor, 0.0002, 7)) {
      union_points.push_back((world_from_sensor.cast<float>() * p));
      towards_sensor.push_back(origin - union_points.back());
    }
  }
  ASSERT_GT(part.mesh.SignedVolume(), 0);  // the faces wind outward
  std::vector<Eigen::Vector3f> outward;
  const std::vector<Eigen::Vector3f> truth = evaluation::SampleSurface(part.mesh, 50000, 5, &outward);
  const Pose3 motion = Motion(110.0, {0.3, -0.5, 0.8}, {0.04, -0.02, 0.01});
  const std::vector<Eigen::Vector3f> moved = MovedPoints(union_points, motion);
  std::vector<Eigen::Vector3f> moved_facing;
  for (const Eigen::Vector3f& d : towards_sensor) moved_facing.push_back(motion.linear().cast<float>() * d);

  FeatureAlignmentOptions options;
  options.voxel_size = 0.002;
  options.source_facing = moved_facing;
  options.target_facing = outward;
  const auto result = AlignByFeatures(moved, truth, options);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  ASSERT_TRUE(result->found) << result->reason;
  EXPECT_FALSE(result->flipped_normals);
  EXPECT_LT(RotationErrorDeg(result->target_from_source, motion.inverse()), 0.3);
  EXPECT_LT(TranslationErrorMm(result->target_from_source, motion.inverse()), 1.0);

  options.target_facing = std::span<const Eigen::Vector3f>(outward).first(10);
  const auto refused = AlignByFeatures(moved, truth, options);
  EXPECT_EQ(refused.status().field(), "features.target_facing");
}

TEST(DescriptorMatchingTest, MutualNearestAgreesWithAPlainSearch) {
  std::mt19937 rng(4);
  std::normal_distribution<float> g(0.0f, 1.0f);
  Eigen::MatrixXf source(16, 700), target(16, 500);
  for (Eigen::Index i = 0; i < source.size(); ++i) source.data()[i] = g(rng);
  for (Eigen::Index i = 0; i < target.size(); ++i) target.data()[i] = g(rng);
  // Some targets are noisy copies of sources, so that there are mutual pairs to find.
  for (Eigen::Index t = 0; t < 300; ++t) target.col(t) = source.col(2 * t) + 0.1f * target.col(t);
  const auto matches = MatchMutualNearest(source, target, nullptr);
  ASSERT_TRUE(matches.ok());
  const auto nearest = [](const Eigen::MatrixXf& from, Eigen::Index column, const Eigen::MatrixXf& to) {
    Eigen::Index best = 0;
    (to.colwise() - from.col(column)).colwise().squaredNorm().minCoeff(&best);
    return best;
  };
  std::vector<DescriptorMatch> expected;
  for (Eigen::Index s = 0; s < source.cols(); ++s) {
    const Eigen::Index t = nearest(source, s, target);
    if (nearest(target, t, source) == s) expected.push_back({static_cast<uint32_t>(s), static_cast<uint32_t>(t)});
  }
  ASSERT_GE(expected.size(), 300u);
  ASSERT_EQ(matches->size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ((*matches)[i].source, expected[i].source);
    EXPECT_EQ((*matches)[i].target, expected[i].target);
  }
}

TEST(MatchConsensusTest, FindsTheMotionWhenNineInTenPairsAreWrong) {
  const Cloud cloud = testing::BoxAndSphere(2000, 9);
  const Pose3 truth = Motion(140.0, {0.3, 0.9, -0.2}, {0.1, -0.2, 0.05});
  std::mt19937 rng(10);
  std::normal_distribution<float> noise(0.0f, 0.001f);
  std::uniform_int_distribution<size_t> any(0, cloud.points.size() - 1);
  std::vector<Eigen::Vector3f> source, target;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    source.push_back(cloud.points[i]);
    const bool right = i % 10 == 0;
    const Eigen::Vector3f& partner = cloud.points[right ? i : any(rng)];
    const Eigen::Vector3f offset(noise(rng), noise(rng), noise(rng));
    target.push_back((truth * partner.cast<double>()).cast<float>() + offset);
  }
  const auto consensus = FindMatchConsensus(source, target, ConsensusOptions{});
  ASSERT_TRUE(consensus.ok());
  EXPECT_GE(consensus->inliers, 190u);
  EXPECT_LT(RotationErrorDeg(consensus->target_from_source, truth), 0.5);
  EXPECT_LT(TranslationErrorMm(consensus->target_from_source, truth), 1.0);
}

}  // namespace
}  // namespace vscan::registration
