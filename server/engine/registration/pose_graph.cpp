#include "registration/pose_graph.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace vscan::registration {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
constexpr size_t kHeld = ~size_t{0};
// Levenberg-Marquardt damping: start, bounds, and the floor that keeps a direction no edge
// constrains (e.g. sliding along a plane) solvable, relative to the largest diagonal term.
constexpr double kInitialDamping = 1e-6;
constexpr double kMinDamping = 1e-12;
constexpr double kMaxDamping = 1e10;
constexpr double kDiagonalFloor = 1e-9;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Vector3d LogRotation(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

Eigen::Matrix3d ExpRotation(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

// The inverse of SO(3)'s right Jacobian: log(R exp(d)) = log(R) + InverseRightJacobian(log R) d + O(d^2).
Eigen::Matrix3d InverseRightJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d k = Skew(phi);
  const double c = theta < 1e-5 ? 1.0 / 12.0
                                 : 1.0 / (theta * theta) - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  return Eigen::Matrix3d::Identity() + 0.5 * k + c * k * k;
}

struct EdgeTerm {
  Vector6d error;
  // Derivatives of the error by the right perturbations (w, t) of the `from` and `to` poses.
  Matrix6d d_from;
  Matrix6d d_to;
};

// See the derivation in docs/ALIGNMENT.md: perturbing `to` by (w, t) multiplies E by (exp(w), t) on
// the right; perturbing `from` multiplies it by measured^-1 (exp(w), t)^-1 measured on the left.
EdgeTerm Evaluate(const PoseGraphEdge& edge, const std::vector<Pose3>& poses) {
  const Pose3 e = edge.measured.inverse() * poses[edge.from].inverse() * poses[edge.to];
  const Eigen::Matrix3d re = e.linear();
  const Eigen::Vector3d te = e.translation();
  const Eigen::Vector3d phi = LogRotation(re);
  const Eigen::Matrix3d jr_inv = InverseRightJacobian(phi);
  const Eigen::Matrix3d rz_t = edge.measured.linear().transpose();
  const Eigen::Vector3d tz = edge.measured.translation();
  EdgeTerm term;
  term.error << phi, te;
  term.d_to.setZero();
  term.d_to.topLeftCorner<3, 3>() = jr_inv;
  term.d_to.bottomRightCorner<3, 3>() = re;
  term.d_from.setZero();
  term.d_from.topLeftCorner<3, 3>() = -jr_inv * re.transpose() * rz_t;
  term.d_from.bottomLeftCorner<3, 3>() = Skew(te) * rz_t + rz_t * Skew(tz);
  term.d_from.bottomRightCorner<3, 3>() = -rz_t;
  return term;
}

struct Robust {
  double weight;
  double cost;
};

Robust Huber(const PoseGraphEdge& edge, const Vector6d& error) {
  const double squared = std::max(0.0, error.dot(edge.information * error));
  const double whitened = std::sqrt(squared);
  const double c = edge.huber_width;
  if (whitened <= c) return {1.0, squared};
  return {c / whitened, 2.0 * c * whitened - c * c};
}

double TotalCost(std::span<const PoseGraphEdge> edges, const std::vector<Pose3>& poses) {
  double cost = 0.0;
  for (const PoseGraphEdge& edge : edges) cost += Huber(edge, Evaluate(edge, poses).error).cost;
  return cost;
}

Status Validate(const std::vector<Pose3>& poses, std::span<const PoseGraphEdge> edges,
                std::span<const size_t> fixed_nodes, const PoseGraphOptions& options) {
  if (fixed_nodes.empty()) return InvalidArgument("pose_graph.fixed_nodes", "needs at least one fixed node");
  for (size_t node : fixed_nodes) {
    if (node >= poses.size()) return InvalidArgument("pose_graph.fixed_nodes", "names a node that does not exist");
  }
  for (const Pose3& pose : poses) {
    if (!pose.matrix().allFinite()) return InvalidArgument("pose_graph.poses", "must be finite");
  }
  for (size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& edge = edges[k];
    const std::string field = "pose_graph.edges[" + std::to_string(k) + "]";
    if (edge.from >= poses.size() || edge.to >= poses.size()) {
      return InvalidArgument(field, "names a node that does not exist");
    }
    if (edge.from == edge.to) return InvalidArgument(field, "joins a node to itself");
    if (!edge.measured.matrix().allFinite()) return InvalidArgument(field + ".measured", "must be finite");
    const Matrix6d& info = edge.information;
    if (!info.allFinite() || (info - info.transpose()).cwiseAbs().maxCoeff() > 1e-9 * info.cwiseAbs().maxCoeff()) {
      return InvalidArgument(field + ".information", "must be finite and symmetric");
    }
    if (!(edge.huber_width > 0.0)) return InvalidArgument(field + ".huber_width", "must be > 0");
  }
  if (options.max_iterations < 1) return InvalidArgument("pose_graph.max_iterations", "must be >= 1");
  if (!(options.rotation_tolerance >= 0.0) || !(options.translation_tolerance >= 0.0)) {
    return InvalidArgument("pose_graph.tolerance", "must be >= 0");
  }
  return Status::Ok();
}

// The variable block of each node that moves, kHeld for the others: fixed nodes and nodes that no
// chain of edges links to a fixed one (nothing pins them, so they stay where they are).
std::vector<size_t> VariableBlocks(size_t nodes, std::span<const PoseGraphEdge> edges,
                                   std::span<const size_t> fixed_nodes, size_t& unconnected) {
  std::vector<std::vector<size_t>> neighbours(nodes);
  for (const PoseGraphEdge& edge : edges) {
    neighbours[edge.from].push_back(edge.to);
    neighbours[edge.to].push_back(edge.from);
  }
  std::vector<char> fixed(nodes, 0), reached(nodes, 0);
  std::vector<size_t> queue;
  for (size_t node : fixed_nodes) {
    fixed[node] = 1;
    if (!reached[node]) queue.push_back(node);
    reached[node] = 1;
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    for (size_t next : neighbours[queue[head]]) {
      if (!reached[next]) {
        reached[next] = 1;
        queue.push_back(next);
      }
    }
  }
  std::vector<size_t> block(nodes, kHeld);
  size_t count = 0;
  unconnected = 0;
  for (size_t node = 0; node < nodes; ++node) {
    if (fixed[node]) continue;
    if (!reached[node]) {
      ++unconnected;
      continue;
    }
    block[node] = count++;
  }
  return block;
}

struct System {
  Eigen::SparseMatrix<double> hessian;
  Eigen::VectorXd gradient;
};

// Gauss-Newton normal equations with each edge's information scaled by its Huber weight at the
// current poses (iteratively reweighted least squares).
System Assemble(std::span<const PoseGraphEdge> edges, const std::vector<Pose3>& poses,
                const std::vector<size_t>& block, size_t variables) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(edges.size() * 4 * 36);
  System system;
  system.gradient = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(6 * variables));
  const auto add_block = [&](size_t row_block, size_t col_block, const Matrix6d& m) {
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) {
        triplets.emplace_back(static_cast<int>(6 * row_block) + r, static_cast<int>(6 * col_block) + c, m(r, c));
      }
    }
  };
  for (const PoseGraphEdge& edge : edges) {
    const size_t a = block[edge.from], b = block[edge.to];
    if (a == kHeld && b == kHeld) continue;
    const EdgeTerm term = Evaluate(edge, poses);
    const Matrix6d info = Huber(edge, term.error).weight * edge.information;
    const Vector6d info_error = info * term.error;
    if (a != kHeld) {
      add_block(a, a, term.d_from.transpose() * info * term.d_from);
      system.gradient.segment<6>(static_cast<Eigen::Index>(6 * a)) += term.d_from.transpose() * info_error;
    }
    if (b != kHeld) {
      add_block(b, b, term.d_to.transpose() * info * term.d_to);
      system.gradient.segment<6>(static_cast<Eigen::Index>(6 * b)) += term.d_to.transpose() * info_error;
    }
    if (a != kHeld && b != kHeld) {
      const Matrix6d cross = term.d_from.transpose() * info * term.d_to;
      add_block(a, b, cross);
      add_block(b, a, cross.transpose());
    }
  }
  system.hessian.resize(system.gradient.size(), system.gradient.size());
  system.hessian.setFromTriplets(triplets.begin(), triplets.end());
  return system;
}

std::vector<Pose3> Apply(const std::vector<Pose3>& poses, const std::vector<size_t>& block,
                         const Eigen::VectorXd& step) {
  std::vector<Pose3> moved = poses;
  for (size_t node = 0; node < poses.size(); ++node) {
    if (block[node] == kHeld) continue;
    const Vector6d d = step.segment<6>(static_cast<Eigen::Index>(6 * block[node]));
    Pose3& pose = moved[node];
    pose.translation() += pose.linear() * d.tail<3>();
    pose.linear() = Eigen::Quaterniond(pose.linear() * ExpRotation(d.head<3>())).normalized().toRotationMatrix();
  }
  return moved;
}

bool SmallStep(const Eigen::VectorXd& step, const PoseGraphOptions& options) {
  for (Eigen::Index k = 0; k < step.size(); k += 6) {
    if (step.segment<3>(k).norm() > options.rotation_tolerance) return false;
    if (step.segment<3>(k + 3).norm() > options.translation_tolerance) return false;
  }
  return true;
}

}  // namespace

StatusOr<PoseGraphResult> OptimizePoseGraph(std::vector<Pose3> poses, std::span<const PoseGraphEdge> edges,
                                            std::span<const size_t> fixed_nodes, const PoseGraphOptions& options) {
  RETURN_IF_ERROR(Validate(poses, edges, fixed_nodes, options));
  PoseGraphResult result;
  const std::vector<size_t> block = VariableBlocks(poses.size(), edges, fixed_nodes, result.unconnected);
  const size_t variables = static_cast<size_t>(std::count_if(block.begin(), block.end(), [](size_t b) {
    return b != kHeld;
  }));
  double cost = TotalCost(edges, poses);
  result.initial_cost = cost;
  double damping = kInitialDamping;
  for (int iteration = 1; variables > 0 && iteration <= options.max_iterations; ++iteration) {
    if (options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed)) {
      return Cancelled("pose graph: cancelled");
    }
    result.iterations = iteration;
    const System system = Assemble(edges, poses, block, variables);
    const Eigen::VectorXd diagonal = system.hessian.diagonal();
    const double floor = kDiagonalFloor * std::max(diagonal.maxCoeff(), 1e-300);
    bool moved = false;
    while (damping <= kMaxDamping) {
      Eigen::SparseMatrix<double> damped = system.hessian;
      for (Eigen::Index k = 0; k < diagonal.size(); ++k) damped.coeffRef(k, k) += damping * (diagonal[k] + floor);
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(damped);
      if (solver.info() == Eigen::Success) {
        const Eigen::VectorXd step = solver.solve(-system.gradient);
        if (step.allFinite()) {
          if (SmallStep(step, options)) {
            poses = Apply(poses, block, step);
            result.converged = true;
            moved = true;
            break;
          }
          std::vector<Pose3> trial = Apply(poses, block, step);
          const double trial_cost = TotalCost(edges, trial);
          if (trial_cost <= cost) {
            poses = std::move(trial);
            cost = trial_cost;
            damping = std::max(damping * 0.1, kMinDamping);
            moved = true;
            break;
          }
        }
      }
      damping *= 10.0;
    }
    // No step lowers the cost any more: the poses are at the minimum to within rounding.
    if (!moved) result.converged = true;
    if (result.converged) break;
  }
  if (variables == 0) result.converged = true;
  result.final_cost = TotalCost(edges, poses);
  result.edge_weights.reserve(edges.size());
  for (const PoseGraphEdge& edge : edges) {
    result.edge_weights.push_back(Huber(edge, Evaluate(edge, poses).error).weight);
  }
  result.poses = std::move(poses);
  return result;
}

}  // namespace vscan::registration
