#pragma once
// Point-to-plane ICP: the rigid transform that lays a source cloud onto a target cloud with
// normals, from a start close enough for nearest neighbours to be mostly right.

#include <cstddef>
#include <numbers>
#include <span>

#include <Eigen/Core>

#include "registration/robust_kernel.h"
#include "registration/target_index.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::registration {

struct IcpOptions {
  // Pairs farther apart than this (metres) are never used.
  double max_correspondence_distance = 0.02;
  // Each iteration also rejects pairs farther apart than this many times the median pair distance,
  // a bound that shrinks with the residuals as the clouds come together; 0 turns this off.
  double rejection_factor = 3.0;
  // With source normals: pairs whose normals differ by more than this (radians, sign ignored) are
  // rejected.
  double max_normal_angle = std::numbers::pi / 4;
  RobustKernel kernel = RobustKernel::kTukey;
  // Kernel width in robust residual scales; 0 picks the kernel's usual constant (see KernelWidth).
  double kernel_width = 0.0;
  // Converged when one iteration turns by less than rotation_tolerance (radians) and moves by less
  // than translation_tolerance (metres).
  double rotation_tolerance = 1e-5;
  double translation_tolerance = 1e-6;
  int max_iterations = 50;
  // Sources larger than twice this start on an evenly spread subset of about this many points and
  // switch to all points once that stage's updates fall below 10 times the tolerances; 0 uses all
  // points from the start.
  size_t coarse_points = 5000;
  // An iteration with fewer accepted pairs than this ends the run, not converged.
  size_t min_correspondences = 32;
};

enum class IcpStop {
  kConverged,              // the last update was below both tolerances
  kMaxIterations,          // still moving after max_iterations
  kTooFewCorrespondences,  // fewer than min_correspondences pairs were accepted
  kDegenerate,             // the pairs do not pin down all six degrees of freedom
};

const char* IcpStopName(IcpStop stop);

struct IcpResult {
  // Maps source coordinates to target coordinates.
  Pose3 target_from_source = Pose3::Identity();
  int iterations = 0;
  bool converged = false;
  IcpStop stop = IcpStop::kMaxIterations;
  // From the last iteration's pairs over the stage's finite source points: the share whose
  // nearest target point lies within max_correspondence_distance.
  double fitness = 0.0;
  // Root mean square point-to-plane distance (metres) of the accepted pairs.
  double inlier_rmse = 0.0;
  size_t correspondences = 0;
  // The last iteration's rejection distance and robust residual scale (metres).
  double rejection_distance = 0.0;
  double residual_scale = 0.0;
  // The last iteration's update: its turn (radians) and move (metres, about the target's centroid).
  double last_rotation_step = 0.0;
  double last_translation_step = 0.0;
};

// Target normals are unit length, one per target point; a target point whose normal or position is
// not finite is never matched. Source normals are optional (empty span) and only used to reject
// pairs. Parallel with TBB; the same inputs give the same result whatever the thread count.
// InvalidArgument names "icp.<option>" for an option out of range, or the mismatched input.
StatusOr<IcpResult> PointToPlaneIcp(std::span<const Eigen::Vector3f> source,
                                    std::span<const Eigen::Vector3f> target,
                                    std::span<const Eigen::Vector3f> target_normals,
                                    const Pose3& initial_target_from_source, const IcpOptions& options,
                                    std::span<const Eigen::Vector3f> source_normals = {});

// The same against a target indexed once for many runs (the source onto one model from many
// starts).
StatusOr<IcpResult> PointToPlaneIcp(std::span<const Eigen::Vector3f> source, const TargetIndex& target,
                                    const Pose3& initial_target_from_source, const IcpOptions& options,
                                    std::span<const Eigen::Vector3f> source_normals = {});

}  // namespace vscan::registration
