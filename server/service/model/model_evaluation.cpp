#include "service/model/model_evaluation.h"

#include <chrono>

#include "evaluation/coverage_image.h"
#include "evaluation/ground_truth.h"
#include "vscan/common/cloud_io.h"

namespace vscan::service {

std::vector<uint8_t> CoveredMask(std::span<const Eigen::Vector3f> samples, std::span<const Eigen::Vector3f> uncovered) {
  std::vector<uint8_t> covered(samples.size(), 1);
  size_t next = 0;
  for (size_t i = 0; i < samples.size() && next < uncovered.size(); ++i) {
    if (samples[i] == uncovered[next]) {
      covered[i] = 0;
      ++next;
    }
  }
  return covered;
}

StatusOr<ModelVerdict> EvaluateModel(const ModelGroundTruth& truth, const ModelCrop& crop, double tau,
                                     std::span<const Eigen::Vector3f> union_points, const TriangleMesh* mesh,
                                     const Eigen::Vector3d& up) {
  const auto start = std::chrono::steady_clock::now();
  const TriangleMesh seen = ClipMesh(truth.mesh, crop);
  if (seen.empty()) return FailedPrecondition("crop", "leaves nothing of the ground truth");
  evaluation::EvaluationOptions options;
  options.tau = tau;
  ASSIGN_OR_RETURN(const evaluation::GroundTruth ground_truth, evaluation::GroundTruth::Prepare(seen, options));

  ModelVerdict verdict;
  ModelEvaluationReport& report = verdict.report;
  report.tau = tau;
  report.objects = truth.object_ids;
  report.area_m2 = ground_truth.area();
  report.samples = ground_truth.samples().size();
  report.union_metrics = ground_truth.EvaluatePoints(union_points);
  report.coverage = report.union_metrics.recall;
  if (mesh && !mesh->empty()) {
    ASSIGN_OR_RETURN(report.mesh_metrics, ground_truth.EvaluateMesh(*mesh));
  }

  verdict.samples = ground_truth.samples();
  verdict.covered = CoveredMask(verdict.samples, report.union_metrics.uncovered.positions);
  ASSIGN_OR_RETURN(verdict.uncovered_ply, EncodePly(report.union_metrics.uncovered));
  evaluation::CoverageImageOptions image;
  image.up = up.normalized().cast<float>();
  ASSIGN_OR_RETURN(verdict.coverage_png, evaluation::RenderCoveragePng(verdict.samples, verdict.covered, image));
  // The report keeps the figures; the uncovered points travel as their own artifact.
  report.union_metrics.uncovered = PointCloud();
  if (report.mesh_metrics) report.mesh_metrics->uncovered = PointCloud();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return verdict;
}

}  // namespace vscan::service
