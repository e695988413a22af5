#include "evaluation/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "evaluation/distance_summary.h"
#include "evaluation/nearest_distances.h"
#include "evaluation/surface_sampling.h"
#include "spatial/kd_tree.h"
#include "raycast/point_queries.h"
#include "raycast/raycast_scene.h"

namespace vscan::evaluation {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

size_t SampleCount(double area, double spacing, size_t max_samples) {
  const double n = std::ceil(area / (spacing * spacing));
  return static_cast<size_t>(std::clamp(n, 1.0, static_cast<double>(max_samples)));
}

StatusOr<std::shared_ptr<const raycast::RaycastScene>> SceneOf(const TriangleMesh& mesh) {
  raycast::SceneInstance instance;
  instance.mesh = std::make_shared<const TriangleMesh>(mesh);
  return raycast::RaycastScene::Build(std::span<const raycast::SceneInstance>(&instance, 1));
}

}  // namespace

double FScore(double precision, double recall) {
  return precision + recall > 0 ? 2 * precision * recall / (precision + recall) : 0;
}

StatusOr<GroundTruth> GroundTruth::Prepare(const TriangleMesh& mesh, const EvaluationOptions& options) {
  if (!(options.tau > 0) || !std::isfinite(options.tau)) {
    return InvalidArgument("evaluation.tau: must be finite and positive");
  }
  if (!(options.sample_spacing >= 0) || !std::isfinite(options.sample_spacing)) {
    return InvalidArgument("evaluation.sample_spacing: must be finite and not negative");
  }
  GroundTruth truth;
  truth.options_ = options;
  truth.spacing_ = options.sample_spacing > 0 ? options.sample_spacing : options.tau / 2;
  truth.area_ = SurfaceArea(mesh);
  if (!(truth.area_ > 0)) return InvalidArgument("ground_truth: the mesh has no area");
  ASSIGN_OR_RETURN(truth.scene_, SceneOf(mesh));
  truth.samples_ = SampleSurface(mesh, SampleCount(truth.area_, truth.spacing_, options.max_samples), options.seed);
  return truth;
}

Evaluation GroundTruth::EvaluatePoints(std::span<const Eigen::Vector3f> points) const {
  const std::vector<float> to_truth = raycast::DistancesToSurface(*scene_, points, kInf);
  const spatial::KdTree tree(points);
  const std::vector<float> from_truth = NearestDistances(tree, samples_);
  return Combine(points, to_truth, from_truth);
}

StatusOr<Evaluation> GroundTruth::EvaluateMesh(const TriangleMesh& mesh) const {
  const double area = SurfaceArea(mesh);
  if (!(area > 0)) return InvalidArgument("reconstruction: the mesh has no area");
  const std::vector<Eigen::Vector3f> points =
      SampleSurface(mesh, SampleCount(area, spacing_, options_.max_samples), options_.seed + 1);
  ASSIGN_OR_RETURN(auto scene, SceneOf(mesh));
  const std::vector<float> to_truth = raycast::DistancesToSurface(*scene_, points, kInf);
  const std::vector<float> from_truth = raycast::DistancesToSurface(*scene, samples_, kInf);
  return Combine(points, to_truth, from_truth);
}

Evaluation GroundTruth::Combine(std::span<const Eigen::Vector3f> points, std::span<const float> to_truth,
                                std::span<const float> from_truth) const {
  Evaluation e;
  e.tau = options_.tau;
  e.reconstruction_points = points.size();
  e.ground_truth_samples = samples_.size();
  const DistanceSummary accuracy = Summarize(to_truth, options_.tau);
  const DistanceSummary completeness = Summarize(from_truth, options_.tau);
  e.precision = accuracy.within_tau;
  e.recall = completeness.within_tau;
  e.f_score = FScore(e.precision, e.recall);
  e.accuracy = {accuracy.mean, accuracy.median};
  e.completeness = {completeness.mean, completeness.median};
  e.chamfer = 0.5 * (accuracy.mean + completeness.mean);
  for (size_t i = 0; i < samples_.size(); ++i) {
    if (!(from_truth[i] <= options_.tau)) e.uncovered.positions.push_back(samples_[i]);
  }
  return e;
}

}  // namespace vscan::evaluation
