#pragma once
// Approximate convex decomposition of a closed mesh (Bullet's HACD, kept inside the .cpp).

#include <vector>

#include <Eigen/Core>

#include "physics/decomposition_store.h"
#include "vscan/common/mesh.h"

namespace vscan::physics {

// When this environment variable names a directory, decompositions are also kept there, one file
// a mesh (decomposition_store.h), and read back by later processes before HACD runs.
inline constexpr const char* kDecompositionCacheVariable = "VSCAN_DECOMPOSITION_CACHE";

// The convex pieces of the mesh, each as the points of its hull relative to `centre`, simplified
// within hull_tolerance_m (SimplifiedHull). A mesh HACD cannot split comes back as one piece: its
// hull. Kept for the process (32 meshes) and, with kDecompositionCacheVariable set, on disk.
std::vector<std::vector<Eigen::Vector3d>> ConvexPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                       double hull_tolerance_m);

// The names under which the pieces of this mesh, centre and tolerance are kept on disk.
PiecesKey DecompositionKey(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double hull_tolerance_m);

}  // namespace vscan::physics
