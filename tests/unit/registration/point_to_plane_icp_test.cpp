#include "registration/point_to_plane_icp.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "icp_test_util.h"
#include "reference_pair.h"
#include "synthetic_shapes.h"

namespace vscan::registration {
namespace {

using testing::Cloud;
using testing::Motion;
using testing::RotationErrorDeg;
using testing::TranslationErrorMm;

StatusOr<IcpResult> Align(const Cloud& source, const Cloud& target, const IcpOptions& options,
                          const Pose3& initial = Pose3::Identity(), bool with_source_normals = false) {
  return PointToPlaneIcp(source.points, target.points, target.normals, initial, options,
                         with_source_normals ? std::span<const Eigen::Vector3f>(source.normals)
                                             : std::span<const Eigen::Vector3f>());
}

// `fraction` of the cloud's size again as points drawn uniformly in its bounding box grown by
// 2 cm, with random unit normals.
void AddUniformOutliers(Cloud& cloud, double fraction, uint32_t seed) {
  Eigen::AlignedBox3f box;
  for (const auto& p : cloud.points) box.extend(p);
  box.min().array() -= 0.02f;
  box.max().array() += 0.02f;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> g(0.0f, 1.0f);
  const auto count = static_cast<size_t>(fraction * static_cast<double>(cloud.points.size()));
  for (size_t i = 0; i < count; ++i) {
    cloud.points.push_back(box.min() + Eigen::Vector3f(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes()));
    cloud.normals.push_back(Eigen::Vector3f(g(rng), g(rng), g(rng)).normalized());
  }
}

TEST(PointToPlaneIcpTest, RecoversAnExactMotionOfBoxAndSphere) {
  const Cloud target = testing::BoxAndSphere(30000, 1);
  const Pose3 truth = Motion(6.0, {0.2, -0.7, 0.4}, {0.012, 0.007, -0.009});
  const Cloud source = testing::Moved(target, truth.inverse());
  IcpOptions options;
  // Just above the rounding of float coordinates.
  options.rotation_tolerance = 1e-8;
  options.translation_tolerance = 1e-8;
  for (size_t coarse : {size_t{0}, size_t{5000}}) {
    options.coarse_points = coarse;
    const auto result = Align(source, target, options);
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    EXPECT_TRUE(result->converged) << IcpStopName(result->stop);
    EXPECT_LT(RotationErrorDeg(result->target_from_source, truth), 1e-6) << "coarse " << coarse;
    EXPECT_LT(TranslationErrorMm(result->target_from_source, truth), 1e-5) << "coarse " << coarse;
    EXPECT_GT(result->fitness, 0.999);
    EXPECT_LT(result->inlier_rmse, 1e-8);
  }
}

TEST(PointToPlaneIcpTest, RecoversTheReferencePair) {
  const auto& pair = testing::LoadReferencePair();
  const auto result = Align(pair.source, pair.target, IcpOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_TRUE(result->converged) << IcpStopName(result->stop);
  EXPECT_LE(RotationErrorDeg(result->target_from_source, pair.target_from_source), 0.01);
  EXPECT_LE(TranslationErrorMm(result->target_from_source, pair.target_from_source), 0.05);
  EXPECT_GT(result->fitness, 0.99);
  // Two independent draws with 0.5 mm noise on each coordinate.
  EXPECT_LT(result->inlier_rmse, 0.001);
}

TEST(PointToPlaneIcpTest, RecoversTheReferencePairWithSourceNormals) {
  const auto& pair = testing::LoadReferencePair();
  const auto result = Align(pair.source, pair.target, IcpOptions{}, Pose3::Identity(), true);
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_TRUE(result->converged);
  EXPECT_LE(RotationErrorDeg(result->target_from_source, pair.target_from_source), 0.01);
  EXPECT_LE(TranslationErrorMm(result->target_from_source, pair.target_from_source), 0.05);
}

TEST(PointToPlaneIcpTest, AStartOutsideTheBasinIsNotReportedAsGood) {
  const auto& pair = testing::LoadReferencePair();
  for (double angle : {90.0, 180.0}) {
    const auto result = Align(pair.source, pair.target, IcpOptions{}, Motion(angle, {1.0, 0.2, 0.1}, {0, 0, 0}));
    ASSERT_TRUE(result.ok()) << result.status().ToString();
    // The case really is a failure...
    ASSERT_GT(RotationErrorDeg(result->target_from_source, pair.target_from_source), 1.0) << angle;
    // ...and the result says so.
    EXPECT_TRUE(!result->converged || result->fitness < 0.9)
        << angle << " deg: " << IcpStopName(result->stop) << ", fitness " << result->fitness;
  }
}

TEST(PointToPlaneIcpTest, NoPairsWithinReachIsTooFewCorrespondences) {
  const auto& pair = testing::LoadReferencePair();
  const auto result = Align(pair.source, pair.target, IcpOptions{}, Motion(0.0, {0, 0, 1}, {1.0, 0.0, 0.0}));
  ASSERT_TRUE(result.ok());
  EXPECT_FALSE(result->converged);
  EXPECT_EQ(result->stop, IcpStop::kTooFewCorrespondences);
  EXPECT_EQ(result->fitness, 0.0);
}

TEST(PointToPlaneIcpTest, TwentyPercentOutliersInBothCloudsDoNotSpoilTheResult) {
  const auto& pair = testing::LoadReferencePair();
  Cloud source = pair.source, target = pair.target;
  AddUniformOutliers(source, 0.2, 11);
  AddUniformOutliers(target, 0.2, 12);
  const auto result = Align(source, target, IcpOptions{});
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result->converged);
  EXPECT_LE(RotationErrorDeg(result->target_from_source, pair.target_from_source), 0.01);
  EXPECT_LE(TranslationErrorMm(result->target_from_source, pair.target_from_source), 0.05);
}

TEST(PointToPlaneIcpTest, RobustWeightsAloneHandleOutliersWithinReach) {
  const auto& pair = testing::LoadReferencePair();
  Cloud source = pair.source, target = pair.target;
  AddUniformOutliers(source, 0.2, 11);
  AddUniformOutliers(target, 0.2, 12);
  // Only the 20 mm reach rejects pairs, so the weights must do the rest.
  IcpOptions options;
  options.rejection_factor = 0.0;
  options.kernel = RobustKernel::kNone;
  const auto plain = Align(source, target, options);
  ASSERT_TRUE(plain.ok());
  EXPECT_GT(RotationErrorDeg(plain->target_from_source, pair.target_from_source), 0.03) << "outliers too weak";
  options.kernel = RobustKernel::kTukey;
  const auto tukey = Align(source, target, options);
  ASSERT_TRUE(tukey.ok());
  EXPECT_TRUE(tukey->converged);
  EXPECT_LE(RotationErrorDeg(tukey->target_from_source, pair.target_from_source), 0.01);
  EXPECT_LE(TranslationErrorMm(tukey->target_from_source, pair.target_from_source), 0.05);
}

TEST(PointToPlaneIcpTest, SourceNormalsRejectPairsThatFaceAnotherWay) {
  const auto& pair = testing::LoadReferencePair();
  Cloud source = pair.source;
  // A fifth of the points again, lifted 2 mm and with normals across the surface's.
  const Eigen::Vector3f lift = pair.target_from_source.linear().transpose().cast<float>() * Eigen::Vector3f(0, 0, 0.002f);
  for (size_t i = 0; i < pair.source.points.size(); i += 5) {
    source.points.push_back(pair.source.points[i] + lift);
    source.normals.push_back(pair.source.normals[i].unitOrthogonal());
  }
  IcpOptions options;
  options.rejection_factor = 0.0;
  options.kernel = RobustKernel::kNone;
  const auto without = Align(source, pair.target, options);
  ASSERT_TRUE(without.ok());
  EXPECT_GT(TranslationErrorMm(without->target_from_source, pair.target_from_source), 0.1) << "lift too weak";
  const auto with = Align(source, pair.target, options, Pose3::Identity(), true);
  ASSERT_TRUE(with.ok());
  EXPECT_TRUE(with->converged);
  EXPECT_LE(RotationErrorDeg(with->target_from_source, pair.target_from_source), 0.01);
  EXPECT_LE(TranslationErrorMm(with->target_from_source, pair.target_from_source), 0.05);
}

TEST(PointToPlaneIcpTest, SameResultWhateverTheThreadCount) {
  const auto& pair = testing::LoadReferencePair();
  IcpOptions options;
  options.max_iterations = 6;
  const auto run = [&](int threads) {
    tbb::task_arena arena(threads);
    return arena.execute([&] { return Align(pair.source, pair.target, options).value(); });
  };
  const IcpResult one = run(1);
  const IcpResult two = run(2);
  const IcpResult again = run(2);
  EXPECT_EQ(one.target_from_source.matrix(), two.target_from_source.matrix());
  EXPECT_EQ(two.target_from_source.matrix(), again.target_from_source.matrix());
  EXPECT_EQ(one.correspondences, two.correspondences);
  EXPECT_EQ(one.inlier_rmse, two.inlier_rmse);
}

TEST(PointToPlaneIcpTest, APlaneAloneIsDegenerate) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-0.1f, 0.1f);
  Cloud plane;
  for (int i = 0; i < 5000; ++i) {
    plane.points.emplace_back(u(rng), u(rng), 0.0f);
    plane.normals.emplace_back(0.0f, 0.0f, 1.0f);
  }
  const auto result = Align(plane, plane, IcpOptions{}, Motion(1.0, {0, 0, 1}, {0.001, 0.0, 0.001}));
  ASSERT_TRUE(result.ok());
  EXPECT_FALSE(result->converged);
  EXPECT_EQ(result->stop, IcpStop::kDegenerate);
}

TEST(PointToPlaneIcpTest, RejectsBadInputsNamingTheField) {
  const Cloud target = testing::BoxAndSphere(100, 1);
  std::vector<Eigen::Vector3f> few_normals(target.normals.begin(), target.normals.end() - 1);
  auto result = PointToPlaneIcp(target.points, target.points, few_normals, Pose3::Identity(), IcpOptions{});
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(result.status().field(), "target_normals");

  const auto bad_option = [&](auto change, const std::string& field) {
    IcpOptions options;
    change(options);
    const auto r = Align(target, target, options);
    ASSERT_FALSE(r.ok()) << field;
    EXPECT_EQ(r.status().field(), field);
  };
  bad_option([](IcpOptions& o) { o.max_correspondence_distance = 0.0; }, "icp.max_correspondence_distance");
  bad_option([](IcpOptions& o) { o.rejection_factor = -1.0; }, "icp.rejection_factor");
  bad_option([](IcpOptions& o) { o.max_normal_angle = 4.0; }, "icp.max_normal_angle");
  bad_option([](IcpOptions& o) { o.rotation_tolerance = -1.0; }, "icp.rotation_tolerance");
  bad_option([](IcpOptions& o) { o.max_iterations = 0; }, "icp.max_iterations");
  bad_option([](IcpOptions& o) { o.min_correspondences = 3; }, "icp.min_correspondences");
}

TEST(PointToPlaneIcpTest, SkipsNonFinitePointsAndNormals) {
  Cloud target = testing::BoxAndSphere(20000, 3);
  const Pose3 truth = Motion(2.0, {0, 1, 0}, {0.002, 0.0, 0.001});
  Cloud source = testing::Moved(target, truth.inverse());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < 200; ++i) {
    source.points[i * 50].x() = nan;
    target.normals[i * 50 + 7].y() = nan;
    target.points[i * 50 + 9].z() = nan;
  }
  const auto result = Align(source, target, IcpOptions{});
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result->converged);
  EXPECT_LT(RotationErrorDeg(result->target_from_source, truth), 1e-3);
}

}  // namespace
}  // namespace vscan::registration
