#pragma once
// A pose graph: node poses that best agree with measured relative poses between pairs of nodes,
// each weighted by its information, by Levenberg-Marquardt on SE(3) with Huber down-weighting
// of edges that disagree with the rest.

#include <atomic>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::registration {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

// The error of an edge is e = (log R_E, t_E) for E = measured^-1 * poses[from]^-1 * poses[to]:
// zero when the poses agree with the measurement, and equal to (w, t) when the relative pose is
// measured * (exp(w), t), a small rotation w and translation t in the `to` node's frame. The
// information weighs e (its inverse is the covariance of the measurement in that parametrisation).
struct PoseGraphEdge {
  size_t from = 0;
  size_t to = 0;
  // The measured pose of node `to` in the frame of node `from`.
  Pose3 measured = Pose3::Identity();
  Matrix6d information = Matrix6d::Identity();
  // Huber width on the whitened error sqrt(e' * information * e); beyond it the edge's weight
  // falls as width / whitened error. Infinity: plain least squares.
  double huber_width = std::numeric_limits<double>::infinity();
};

struct PoseGraphOptions {
  int max_iterations = 100;
  // Converged when no node turns by more than rotation_tolerance (radians) or moves by more than
  // translation_tolerance (metres) in one step.
  double rotation_tolerance = 1e-10;
  double translation_tolerance = 1e-10;
  // Polled between iterations; when it turns true the call returns Cancelled.
  const std::atomic<bool>* cancel = nullptr;
};

struct PoseGraphResult {
  std::vector<Pose3> poses;
  // Each edge's final Huber weight, 1 for an edge within its width.
  std::vector<double> edge_weights;
  // Nodes neither fixed nor linked to a fixed node by a chain of edges; they keep their pose.
  size_t unconnected = 0;
  int iterations = 0;
  bool converged = false;
  // Sum over edges of the Huber cost of the whitened error (the squared error within the width).
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

// Moves every node except the fixed ones (at least one) to minimise the total cost. The same
// inputs give the same result. InvalidArgument names "pose_graph.<field>" for an edge with an
// unknown node, a loop edge, a non-finite or non-symmetric information, or a bad option.
StatusOr<PoseGraphResult> OptimizePoseGraph(std::vector<Pose3> poses, std::span<const PoseGraphEdge> edges,
                                            std::span<const size_t> fixed_nodes, const PoseGraphOptions& options);

}  // namespace vscan::registration
