#pragma once
// How firmly a fitted pair of clouds pins their relative pose: the Gauss-Newton Hessian of the
// pair's point-to-plane residuals, for a pose-graph edge.

#include <span>

#include <Eigen/Core>

#include "registration/point_to_plane_icp.h"
#include "registration/pose_graph.h"
#include "registration/target_index.h"
#include "vscan/common/pose.h"

namespace vscan::registration {

struct PairInformation {
  // Sum over pairs of w J'J / sigma^2 with J = (p x m, m): p the source point, m the target
  // normal in the source frame, w the robust weight. This is the information over the right
  // perturbation (w, t) of target_from_source that PoseGraphEdge uses.
  Matrix6d information = Matrix6d::Zero();
  // Weighted RMS point-to-plane residual (metres), at least the floor given.
  double sigma = 0.0;
  // Sum of the weights, the effective number of pairs.
  double weight_sum = 0.0;
};

// Pairs each source point, under target_from_source, with its nearest target point within the
// fit's rejection distance, drops pairs whose normals differ by more than the ICP's
// max_normal_angle (when source normals are given), and weighs residuals with the ICP's kernel at
// the fit's residual scale (at least sigma_floor), as the fit's last iteration did.
PairInformation ComputePairInformation(std::span<const Eigen::Vector3f> source,
                                       std::span<const Eigen::Vector3f> source_normals, const TargetIndex& target,
                                       const Pose3& target_from_source, const IcpResult& fit,
                                       const IcpOptions& options, double sigma_floor);

}  // namespace vscan::registration
