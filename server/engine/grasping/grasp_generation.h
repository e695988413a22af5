#pragma once
// Grasps of one part in the part's frame for a suction cup or parallel jaws, from seeded surface
// samples of its mesh (metres). See docs/GRASPING.md for the method and its limits.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "grasping/gripper.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::grasping {

struct GraspOptions {
  size_t max_grasps = 100;          // the best this many are kept, in [1, 100000]
  uint64_t seed = 1;
  size_t surface_samples = 20000;   // dense samples for flatness, coverage and finger checks, [100, 2000000]
  size_t candidates = 1000;         // candidate contact points drawn, [1, 100000]
  size_t approaches_per_pair = 8;   // jaws: approach directions around the grasp axis, [1, 64]
  // Suction: the largest distance of a sample under the cup from the tangent plane.
  double flatness_tolerance_m = 0.0005;
};

struct Grasp {
  // Tool frame in the part frame: z along the approach into the part, origin at the cup's centre
  // on the surface or midway between the jaw contacts; for jaws, y along the closing axis.
  Pose3 part_from_tool = Pose3::Identity();
  Eigen::Vector3d approach = Eigen::Vector3d::UnitZ();
  double quality = 0;     // in [0, 1]
  double opening_m = 0;   // jaws: the distance between the contacts; 0 for suction
};

// INVALID_ARGUMENT naming "grasp_options.*" for a value out of its range.
Status ValidateGraspOptions(const GraspOptions& options);
// RESOURCE_EXHAUSTED naming "grasp_options.candidates" when a search of a part of this many
// triangles would pass the bound GenerateGrasps holds to (below).
Status CheckGraspWork(size_t triangles, const Gripper& gripper, const GraspOptions& options);

// Sorted by quality (rounded to 1e-9), best first, ties by draw order; the same seed gives the same
// grasps.
// InvalidArgument for a bad gripper (naming its field), options ("grasp_options.*") or mesh ("mesh");
// ResourceExhausted ("grasp_options.candidates") when candidates x surface_samples (suction) or
// candidates x (triangles + 2 x surface_samples x approaches_per_pair) (jaws) exceeds 2e9.
StatusOr<std::vector<Grasp>> GenerateGrasps(const TriangleMesh& mesh, const Gripper& gripper,
                                            const GraspOptions& options);

}  // namespace vscan::grasping
