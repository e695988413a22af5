#pragma once
// The true surface prepared once (a closest-point structure and area samples) to evaluate any
// number of reconstructions of it: the scanned union, a TSDF mesh, a Poisson mesh.
//
// Reconstruction -> truth distances are exact point-to-triangle distances (Embree closest-point
// queries), not distances to samples, so precision does not depend on the sampling density.

#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "evaluation/metrics.h"
#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::raycast {
class RaycastScene;
}

namespace vscan::evaluation {

class GroundTruth {
 public:
  // mesh in world coordinates. InvalidArgument names "evaluation.tau", "evaluation.sample_spacing"
  // or "ground_truth" (an empty or degenerate mesh).
  static StatusOr<GroundTruth> Prepare(const TriangleMesh& mesh, const EvaluationOptions& options);

  // A reconstructed point set, e.g. the union of the scans (then recall is its coverage).
  Evaluation EvaluatePoints(std::span<const Eigen::Vector3f> points) const;
  // A reconstructed mesh: sampled at the same spacing for precision; recall measures the truth's
  // samples against its surface.
  StatusOr<Evaluation> EvaluateMesh(const TriangleMesh& mesh) const;

  const std::vector<Eigen::Vector3f>& samples() const { return samples_; }
  double area() const { return area_; }

 private:
  GroundTruth() = default;
  Evaluation Combine(std::span<const Eigen::Vector3f> points, std::span<const float> to_truth,
                     std::span<const float> from_truth) const;

  EvaluationOptions options_;
  double spacing_ = 0;
  double area_ = 0;
  std::shared_ptr<const raycast::RaycastScene> scene_;
  std::vector<Eigen::Vector3f> samples_;
};

}  // namespace vscan::evaluation
