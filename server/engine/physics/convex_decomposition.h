#pragma once
// Approximate convex decomposition of a closed mesh by plane cuts (plane_cut_decomposition.h),
// cached per mesh in the process and on disk.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "physics/decomposition_store.h"
#include "vscan/common/mesh.h"

namespace vscan::physics {

// The process's directory for decompositions (empty, the default: none). When set, pieces are also
// kept there, one file a mesh (decomposition_store.h), and read back by later processes before
// any cut; vscand sets <data dir>/decompositions.
void SetDecompositionDirectory(std::string dir);
std::string DecompositionDirectory();

// A piece's hull may reach at most this share of the part's largest extent from its solid
// (PlaneCutPieces), in at most this many pieces: a compound's cost in the fill grows with its
// pieces, and four open a bore or a notch (decomposition_bench, docs/PHYSICS.md).
inline constexpr double kDecompositionConcavityShare = 0.05;
inline constexpr size_t kMaxDecompositionPieces = 4;

// The convex pieces of the mesh, each as the points of its hull relative to `centre`, simplified
// within hull_tolerance_m (SimplifiedHull). A mesh convex within that tolerance, or whose hull
// already lies within the concavity bound, comes back as one piece: its hull. Kept for the process (32 meshes) and, with a DecompositionDirectory, on disk.
std::vector<std::vector<Eigen::Vector3d>> ConvexPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                       double hull_tolerance_m);

// The names under which the pieces of this mesh, centre and tolerance are kept on disk.
PiecesKey DecompositionKey(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double hull_tolerance_m);

}  // namespace vscan::physics
