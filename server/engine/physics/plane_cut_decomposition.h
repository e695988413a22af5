#pragma once
// Approximate convex decomposition by plane cuts: the mesh's solid is cut by planes until the hull
// of every piece lies within a concavity bound of the solid.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::physics {

struct PlaneCutOptions {
  // How far a piece's hull may reach from the solid (metres): the farthest point of the hull's
  // surface from the mesh, over points that lie outside it.
  double concavity_m = 0.001;
  size_t max_pieces = 16;
};

// The pieces of a closed mesh, each as the vertices of its convex hull relative to `centre`. The
// piece that reaches farthest is cut first, until every piece is within the bound or there are
// max_pieces (a piece no cut brings nearer, such as a blind pocket's, keeps its reach). A cut is
// the one that lowers the worst reach most: one plane (across the part's axes through concave
// corners or at a grid, or along the surface deepest under the hull), or two through the hull's
// middle or its farthest point (a tube, a ring, a bore at an angle); failing that, a plane that
// takes 2% of the whole hull's volume. Deterministic; linear in the triangles for each cut tried.
std::vector<std::vector<Eigen::Vector3d>> PlaneCutPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                         const PlaneCutOptions& options);

// How far the hull of `points` (relative to `centre`) reaches from the mesh's solid: the farthest
// of its surface samples, `step` metres apart (however many that takes), that lies outside the mesh.
double HullReach(const TriangleMesh& mesh, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& points,
                 double step);

}  // namespace vscan::physics
