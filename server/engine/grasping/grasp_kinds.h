#pragma once
// The two generators behind GenerateGrasps; inputs are validated by the caller. Each returns its
// grasps in candidate order (unsorted).

#include <vector>

#include "grasping/grasp_generation.h"
#include "grasping/surface_samples.h"

namespace vscan::grasping {

std::vector<Grasp> SuctionGrasps(const SurfaceSamples& dense, const SurfaceSamples& candidates,
                                 const SuctionCup& cup, const GraspOptions& options);

std::vector<Grasp> JawGrasps(const TriangleMesh& mesh, const SurfaceSamples& dense, const SurfaceSamples& candidates,
                             const ParallelJaws& jaws, const GraspOptions& options);

// INVALID_ARGUMENT naming "mesh": no triangles, an index out of range, a non-finite vertex or larger
// than 100 m.
Status ValidatePartMesh(const TriangleMesh& mesh);

// Two unit vectors completing the unit vector z to a right-handed orthonormal basis (x, y, z).
void PerpendicularBasis(const Eigen::Vector3d& z, Eigen::Vector3d& x, Eigen::Vector3d& y);

}  // namespace vscan::grasping
