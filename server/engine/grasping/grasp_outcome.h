#pragma once
// Would a grasp planned on an estimated pose of a part have held the part where it truly lies?
// The suction cup or the jaws run to the planned tool pose against the true part's mesh.

#include <memory>
#include <string>

#include "grasping/grasp_generation.h"
#include "grasping/gripper.h"
#include "grasping/mesh_rays.h"
#include "grasping/suction_seal.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::grasping {

struct GraspOutcome {
  bool holds = false;
  std::string why;  // empty when it holds: "the cup meets no surface", "the cup does not seal", ...
  // Suction: how far beyond the planned contact the true surface lies along the approach
  // (negative: nearer, taken up by the stroke). Jaws: the width the fingers close on.
  double contact_offset_m = 0;
};

struct OutcomeOptions {
  // Suction: the cup stops this far past its planned contact (the arm's overtravel) at most.
  double overtravel_m = 0.002;
  double flatness_tolerance_m = 0.0005;
  size_t surface_samples = 20000;
  uint64_t seed = 1;
};

// One part type's true geometry, prepared once for many grasps.
class GraspTarget {
 public:
  // INVALID_ARGUMENT naming "mesh" or the gripper's field.
  static StatusOr<std::shared_ptr<const GraspTarget>> Make(const TriangleMesh& mesh, const Gripper& gripper,
                                                           const OutcomeOptions& options = {});

  // grasp is in the estimated part's frame; truth_from_estimate = world_from_truth^-1 * world_from_estimate.
  // Suction: the cup advances along its axis from a stroke behind the planned contact; it holds
  // when it meets an outward face no farther than overtravel past the contact, that face is
  // within max_tilt of the cup's axis, and the cup seals there (suction_seal.h). Jaws: each finger
  // closes from the open jaw along the closing axis through the tool centre; they hold when both
  // land on outward faces, within the friction cone of the axis, at a width of at least
  // min_opening (less the flatness tolerance).
  GraspOutcome Try(const Grasp& grasp, const Pose3& truth_from_estimate) const;

 private:
  GraspTarget(const TriangleMesh& mesh, const Gripper& gripper, const OutcomeOptions& options);
  GraspOutcome TrySuction(const SuctionCup& cup, const Pose3& truth_from_tool) const;
  GraspOutcome TryJaws(const ParallelJaws& jaws, const Pose3& truth_from_tool) const;

  Gripper gripper_;
  OutcomeOptions options_;
  MeshRays rays_;
  SurfaceSamples dense_;
  std::unique_ptr<SampleGrid> grid_;
  std::unique_ptr<DiscCells> disc_;
};

}  // namespace vscan::grasping
