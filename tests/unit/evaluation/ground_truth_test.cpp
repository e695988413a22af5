#include "evaluation/ground_truth.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "evaluation/surface_sampling.h"
#include "random/seeded_draws.h"
#include "vscan_test/meshes.h"

namespace vscan::evaluation {
namespace {

constexpr double kTruthTau = 0.002;
constexpr double kTruthRadius = 0.1;

GroundTruth Prepare(const TriangleMesh& mesh, double tau = kTruthTau) {
  EvaluationOptions options;
  options.tau = tau;
  auto truth = GroundTruth::Prepare(mesh, options);
  EXPECT_TRUE(truth.ok()) << truth.status().ToString();
  return std::move(truth).value();
}

// Points on the mesh, each moved by up to `noise` along a random direction.
std::vector<Eigen::Vector3f> NoisySamples(const TriangleMesh& mesh, size_t n, double noise, uint64_t seed) {
  std::vector<Eigen::Vector3f> points = SampleSurface(mesh, n, seed);
  random::SplitMix64Stream draws(seed);
  for (auto& p : points) {
    const Eigen::Vector3f dir(draws.Uniform() - 0.5, draws.Uniform() - 0.5, draws.Uniform() - 0.5);
    p += static_cast<float>(noise) * dir.normalized();
  }
  return points;
}

TEST(GroundTruth, SphereSamplesWithNoiseBelowTauScorePerfectly) {
  const TriangleMesh sphere = test::MakeIcosphere(Eigen::Vector3d::Zero(), kTruthRadius, 4);
  const GroundTruth truth = Prepare(sphere);
  // About one point per (tau / 2.8)^2 of area, each off the surface by a quarter of tau.
  const auto points = NoisySamples(sphere, 250'000, kTruthTau / 4, 3);
  const Evaluation e = truth.EvaluatePoints(points);
  EXPECT_DOUBLE_EQ(e.precision, 1.0);
  EXPECT_DOUBLE_EQ(e.recall, 1.0);
  EXPECT_DOUBLE_EQ(e.f_score, 1.0);
  EXPECT_TRUE(e.uncovered.positions.empty());
  EXPECT_LE(e.accuracy.mean, kTruthTau / 4 + 1e-6);
  EXPECT_GT(e.accuracy.mean, kTruthTau / 16);
  EXPECT_LT(e.chamfer, kTruthTau / 2);
  EXPECT_EQ(e.reconstruction_points, points.size());
  // tau / 2 spacing: about area / spacing^2 samples.
  EXPECT_NEAR(static_cast<double>(e.ground_truth_samples), truth.area() / (kTruthTau * kTruthTau / 4), 1.0);
}

TEST(GroundTruth, PlaneShiftedByTwiceTauScoresZero) {
  const TriangleMesh plane = test::MakeGrid(0.05, 4);
  const GroundTruth truth = Prepare(plane);
  std::vector<Eigen::Vector3f> points = SampleSurface(plane, 20'000, 5);
  for (auto& p : points) p.z() += 2 * kTruthTau;
  const Evaluation e = truth.EvaluatePoints(points);
  EXPECT_EQ(e.precision, 0.0);
  EXPECT_EQ(e.recall, 0.0);
  EXPECT_EQ(e.f_score, 0.0);
  EXPECT_EQ(e.uncovered.size(), e.ground_truth_samples);
  EXPECT_NEAR(e.accuracy.mean, 2 * kTruthTau, 1e-6);
  EXPECT_NEAR(e.accuracy.median, 2 * kTruthTau, 1e-6);
  EXPECT_GE(e.completeness.median, 2 * kTruthTau - 1e-6);
}

// Mean distance from a sphere of radius r to the same sphere shifted by d: the distance of the
// point at cos(angle) = t from the shift is |sqrt(r^2 + d^2 - 2 r d t) - r|, t uniform on [-1, 1].
double MeanDistanceToShiftedSphere(double r, double d) {
  constexpr int kSteps = 200'000;
  double sum = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double t = -1.0 + (i + 0.5) * 2.0 / kSteps;
    sum += std::abs(std::sqrt(r * r + d * d - 2 * r * d * t) - r);
  }
  return sum / kSteps;
}

TEST(GroundTruth, SphereShiftedByAKnownDistanceScoresTauOverTheShift) {
  const TriangleMesh sphere = test::MakeIcosphere(Eigen::Vector3d::Zero(), kTruthRadius, 5);
  const GroundTruth truth = Prepare(sphere);
  const double shift = 4 * kTruthTau;
  std::vector<Eigen::Vector3f> points = SampleSurface(sphere, 400'000, 7);
  for (auto& p : points) p.x() += static_cast<float>(shift);
  const Evaluation e = truth.EvaluatePoints(points);
  // |distance| <= tau on a band of the sphere whose share of its area is exactly tau / shift, both
  // ways: precision = recall = F = 1/4.
  EXPECT_NEAR(e.precision, kTruthTau / shift, 0.01);
  EXPECT_NEAR(e.recall, kTruthTau / shift, 0.01);
  EXPECT_NEAR(e.f_score, kTruthTau / shift, 0.01);
  const double mean = MeanDistanceToShiftedSphere(kTruthRadius, shift);
  EXPECT_NEAR(e.accuracy.mean, mean, 0.02 * mean);
  EXPECT_NEAR(e.completeness.mean, mean, 0.02 * mean);
  EXPECT_NEAR(e.chamfer, mean, 0.02 * mean);
}

TEST(GroundTruth, HalfASphereHasHalfTheRecallAndFullPrecision) {
  const TriangleMesh sphere = test::MakeIcosphere(Eigen::Vector3d::Zero(), kTruthRadius, 4);
  const GroundTruth truth = Prepare(sphere);
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : SampleSurface(sphere, 300'000, 9)) {
    if (p.z() > 0) points.push_back(p);
  }
  const Evaluation e = truth.EvaluatePoints(points);
  EXPECT_DOUBLE_EQ(e.precision, 1.0);
  // Samples within tau below the cut are covered too: a band of height tau on the equator.
  EXPECT_NEAR(e.recall, 0.5 + kTruthTau / (2 * kTruthRadius), 0.01);
  EXPECT_NEAR(e.f_score, 2 * e.recall / (1 + e.recall), 1e-12);
  for (const auto& p : e.uncovered.positions) EXPECT_LT(p.z(), 0.0f);
  EXPECT_NEAR(static_cast<double>(e.uncovered.size()) / e.ground_truth_samples, 1 - e.recall, 1e-12);
}

TEST(GroundTruth, ChamferOfAnOffsetPlaneMeshIsTheOffset) {
  const TriangleMesh plane = test::MakeGrid(0.05, 4);
  const GroundTruth truth = Prepare(plane);
  constexpr double kOffset = 0.003;
  TriangleMesh lifted = plane;
  for (auto& v : lifted.vertices) v.z() += static_cast<float>(kOffset);
  auto e = truth.EvaluateMesh(lifted);
  ASSERT_TRUE(e.ok()) << e.status().ToString();
  EXPECT_NEAR(e->accuracy.mean, kOffset, 1e-6);
  EXPECT_NEAR(e->completeness.mean, kOffset, 1e-6);
  EXPECT_NEAR(e->chamfer, kOffset, 1e-6);
  EXPECT_EQ(e->f_score, 0.0);
  // With tau above the offset every point is within tau both ways.
  auto near = Prepare(plane, 2 * kOffset).EvaluateMesh(lifted);
  ASSERT_TRUE(near.ok());
  EXPECT_EQ(near->f_score, 1.0);
}

TEST(GroundTruth, RejectsBadOptionsAndEmptyMeshes) {
  EvaluationOptions options;
  options.tau = 0;
  auto bad_tau = GroundTruth::Prepare(test::MakeGrid(1, 1), options);
  ASSERT_FALSE(bad_tau.ok());
  EXPECT_NE(bad_tau.status().message().find("evaluation.tau"), std::string::npos);
  auto empty = GroundTruth::Prepare(TriangleMesh{}, EvaluationOptions{});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.status().message().find("ground_truth"), std::string::npos);
}

TEST(GroundTruth, EmptyReconstructionHasNoRecall) {
  const GroundTruth truth = Prepare(test::MakeGrid(0.05, 2));
  const Evaluation e = truth.EvaluatePoints({});
  EXPECT_EQ(e.precision, 0.0);
  EXPECT_EQ(e.recall, 0.0);
  EXPECT_EQ(e.uncovered.size(), e.ground_truth_samples);
}

}  // namespace
}  // namespace vscan::evaluation
