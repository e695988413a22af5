#include "registration/pose_graph.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "icp_test_util.h"

namespace vscan::registration {
namespace {

using testing::kDeg;
using testing::Motion;
using testing::RotationErrorDeg;
using testing::TranslationErrorMm;

Pose3 RandomPose(std::mt19937& rng, double max_angle_deg, double max_shift) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Motion(max_angle_deg * u(rng), {u(rng), u(rng), u(rng)},
                max_shift * Eigen::Vector3d(u(rng), u(rng), u(rng)));
}

// Node k at angle 45k degrees on a circle of radius 0.4 m, facing the centre.
std::vector<Pose3> RingPoses(int count) {
  std::vector<Pose3> poses;
  for (int k = 0; k < count; ++k) {
    Pose3 pose = Pose3::Identity();
    pose.linear() = Eigen::AngleAxisd(2.0 * std::numbers::pi * k / count, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = pose.linear() * Eigen::Vector3d(0.4, 0.0, 0.0);
    poses.push_back(pose);
  }
  return poses;
}

PoseGraphEdge ExactEdge(const std::vector<Pose3>& truth, size_t from, size_t to) {
  PoseGraphEdge edge;
  edge.from = from;
  edge.to = to;
  edge.measured = truth[from].inverse() * truth[to];
  return edge;
}

// A ring with consecutive edges, a few chords, edges in both directions.
std::vector<PoseGraphEdge> RingEdges(const std::vector<Pose3>& truth) {
  std::vector<PoseGraphEdge> edges;
  const size_t n = truth.size();
  for (size_t k = 0; k < n; ++k) {
    edges.push_back(k % 2 == 0 ? ExactEdge(truth, k, (k + 1) % n) : ExactEdge(truth, (k + 1) % n, k));
  }
  edges.push_back(ExactEdge(truth, 0, n / 2));
  edges.push_back(ExactEdge(truth, n / 2 + 1, 1));
  return edges;
}

TEST(PoseGraphTest, ExactMeasurementsGiveTheTruePosesFromPerturbedStarts) {
  const std::vector<Pose3> truth = RingPoses(8);
  std::vector<PoseGraphEdge> edges = RingEdges(truth);
  // Anisotropic, correlated information, as a point-to-plane fit gives.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto& edge : edges) {
    Matrix6d a = Matrix6d::NullaryExpr([&](Eigen::Index, Eigen::Index) { return u(rng); });
    edge.information = a * a.transpose() + 0.1 * Matrix6d::Identity();
  }
  std::vector<Pose3> start = truth;
  for (size_t k = 1; k < start.size(); ++k) start[k] = RandomPose(rng, 5.0, 0.03) * start[k];
  const size_t anchor = 0;
  const auto result = OptimizePoseGraph(start, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_TRUE(result->converged);
  EXPECT_GT(result->initial_cost, 1e-3);
  EXPECT_LT(result->final_cost, 1e-12);
  EXPECT_EQ(result->poses[0].matrix(), truth[0].matrix());
  for (size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT(RotationErrorDeg(result->poses[k], truth[k]), 1e-7) << k;
    EXPECT_LT(TranslationErrorMm(result->poses[k], truth[k]), 1e-6) << k;
  }
}

// Two measurements of one node against the fixed one, isotropic information w1 and w2: the best
// rotation is the point w2 / (w1 + w2) of the way along the geodesic from the first measured
// rotation to the second, the best translation the weighted mean.
TEST(PoseGraphTest, TwoMeasurementsFromTheAnchorMeetAtTheirWeightedMean) {
  const Pose3 a = Motion(20.0, {0.3, 1.0, -0.2}, {0.10, -0.05, 0.30});
  const Pose3 b = Motion(3.0, {1.0, -0.4, 0.7}, {0.004, 0.002, -0.003}) * a;
  const double w1 = 1.0, w2 = 3.0;
  std::vector<PoseGraphEdge> edges(2);
  edges[0].from = edges[1].from = 0;
  edges[0].to = edges[1].to = 1;
  edges[0].measured = a;
  edges[1].measured = b;
  edges[0].information = w1 * Matrix6d::Identity();
  edges[1].information = w2 * Matrix6d::Identity();
  const size_t anchor = 0;
  const auto result = OptimizePoseGraph({Pose3::Identity(), Pose3::Identity()}, edges,
                                        std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  const double share = w2 / (w1 + w2);
  const Eigen::AngleAxisd between(a.linear().transpose() * b.linear());
  Pose3 expected = Pose3::Identity();
  expected.linear() = a.linear() * Eigen::AngleAxisd(share * between.angle(), between.axis()).toRotationMatrix();
  expected.translation() = (w1 * a.translation() + w2 * b.translation()) / (w1 + w2);
  EXPECT_LT(RotationErrorDeg(result->poses[1], expected), 1e-8);
  EXPECT_LT(TranslationErrorMm(result->poses[1], expected), 1e-8);
}

// The same with the edges pointing at the fixed node: the error of node 1 then enters through the
// `from` side. With measured poses m_k of node 0 in node 1's frame, the best inverse rotation is the
// weighted geodesic point between the m_k's rotations and R^T t is minus the weighted mean of their
// translations.
TEST(PoseGraphTest, TwoMeasurementsTowardsTheAnchorMeetAtTheirWeightedMean) {
  const Pose3 a = Motion(-15.0, {0.1, 0.2, 1.0}, {-0.2, 0.05, 0.1});
  const Pose3 b = Motion(2.5, {-0.3, 1.0, 0.4}, {-0.003, 0.005, 0.001}) * a;
  const double w1 = 2.0, w2 = 1.0;
  std::vector<PoseGraphEdge> edges(2);
  edges[0].from = edges[1].from = 1;
  edges[0].to = edges[1].to = 0;
  edges[0].measured = a;
  edges[1].measured = b;
  edges[0].information = w1 * Matrix6d::Identity();
  edges[1].information = w2 * Matrix6d::Identity();
  const size_t anchor = 0;
  const auto result = OptimizePoseGraph({Pose3::Identity(), Pose3::Identity()}, edges,
                                        std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  const double share = w2 / (w1 + w2);
  const Eigen::AngleAxisd between(a.linear().transpose() * b.linear());
  const Eigen::Matrix3d inverse_rotation =
      a.linear() * Eigen::AngleAxisd(share * between.angle(), between.axis()).toRotationMatrix();
  Pose3 expected = Pose3::Identity();
  expected.linear() = inverse_rotation.transpose();
  expected.translation() = -expected.linear() * (w1 * a.translation() + w2 * b.translation()) / (w1 + w2);
  EXPECT_LT(RotationErrorDeg(result->poses[1], expected), 1e-8);
  EXPECT_LT(TranslationErrorMm(result->poses[1], expected), 1e-8);
}

TEST(PoseGraphTest, HuberWeightsKeepAWrongEdgeFromBendingTheRing) {
  const std::vector<Pose3> truth = RingPoses(8);
  std::vector<PoseGraphEdge> edges = RingEdges(truth);
  // A chord 3 degrees and 3 cm off.
  PoseGraphEdge wrong = ExactEdge(truth, 2, 6);
  wrong.measured = wrong.measured * Motion(3.0, {0, 1, 0}, {0.03, 0.0, 0.0});
  edges.push_back(wrong);
  const size_t anchor = 0;
  const auto max_error_mm = [&](double huber_width) {
    for (auto& edge : edges) edge.huber_width = huber_width;
    const auto result = OptimizePoseGraph(truth, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
    EXPECT_TRUE(result.ok());
    double worst = 0.0;
    for (size_t k = 0; k < truth.size(); ++k) worst = std::max(worst, TranslationErrorMm(result->poses[k], truth[k]));
    return std::make_pair(worst, result->edge_weights.back());
  };
  const auto [plain, plain_weight] = max_error_mm(std::numeric_limits<double>::infinity());
  // Identity information: whitened errors are in radians and metres; 1 mm is well below the wrong
  // edge's error.
  const auto [robust, robust_weight] = max_error_mm(0.001);
  EXPECT_GT(plain, 3.0) << "the wrong edge should bend a plain least-squares ring";
  EXPECT_EQ(plain_weight, 1.0);
  EXPECT_LT(robust, 0.1 * plain);
  EXPECT_LT(robust_weight, 0.1);
}

TEST(PoseGraphTest, ANodeWithoutEdgesToTheAnchorKeepsItsPose) {
  const std::vector<Pose3> truth = RingPoses(4);
  std::vector<Pose3> start = truth;
  start[1] = Motion(1.0, {0, 0, 1}, {0.01, 0, 0}) * start[1];
  start[3] = Motion(2.0, {0, 1, 0}, {0, 0.01, 0}) * start[3];
  // 0-1 linked; 2-3 linked to each other only.
  const std::vector<PoseGraphEdge> edges = {ExactEdge(truth, 0, 1), ExactEdge(truth, 2, 3)};
  const size_t anchor = 0;
  const auto result = OptimizePoseGraph(start, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  ASSERT_TRUE(result.ok()) << result.status().ToString();
  EXPECT_EQ(result->unconnected, 2u);
  EXPECT_LT(TranslationErrorMm(result->poses[1], truth[1]), 1e-6);
  EXPECT_EQ(result->poses[2].matrix(), start[2].matrix());
  EXPECT_EQ(result->poses[3].matrix(), start[3].matrix());
}

TEST(PoseGraphTest, RejectsBadInputsNamingTheField) {
  const std::vector<Pose3> poses = RingPoses(3);
  const size_t anchor = 0, missing = 5;
  std::vector<PoseGraphEdge> edges = {ExactEdge(poses, 0, 1)};
  auto result = OptimizePoseGraph(poses, edges, {}, PoseGraphOptions{});
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().field(), "pose_graph.fixed_nodes");
  result = OptimizePoseGraph(poses, edges, std::span<const size_t>(&missing, 1), PoseGraphOptions{});
  EXPECT_EQ(result.status().field(), "pose_graph.fixed_nodes");
  edges[0].to = 7;
  result = OptimizePoseGraph(poses, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  EXPECT_EQ(result.status().field(), "pose_graph.edges[0]");
  edges[0].to = 0;
  result = OptimizePoseGraph(poses, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  EXPECT_EQ(result.status().field(), "pose_graph.edges[0]");
  edges[0] = ExactEdge(poses, 0, 1);
  edges[0].information(0, 1) = 1.0;
  result = OptimizePoseGraph(poses, edges, std::span<const size_t>(&anchor, 1), PoseGraphOptions{});
  EXPECT_EQ(result.status().field(), "pose_graph.edges[0].information");
  EXPECT_EQ(result.status().code(), StatusCode::kInvalidArgument);
}

TEST(PoseGraphTest, CancelReturnsCancelled) {
  const std::vector<Pose3> truth = RingPoses(8);
  const std::atomic<bool> cancel{true};
  PoseGraphOptions options;
  options.cancel = &cancel;
  std::vector<Pose3> start = truth;
  start[3] = Motion(1.0, {0, 0, 1}, {0.01, 0, 0}) * start[3];
  const size_t anchor = 0;
  const auto result = OptimizePoseGraph(start, RingEdges(truth), std::span<const size_t>(&anchor, 1), options);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kCancelled);
}

}  // namespace
}  // namespace vscan::registration
