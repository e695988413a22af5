#pragma once
// What the fill needs of a part's mesh: its centre of mass, mass, a reduced convex hull, the
// radius of the sphere about its centre of mass that holds the hull, and for
// PartCollision::kConvexDecomposition its convex pieces.

#include <vector>

#include <Eigen/Core>

#include "physics/bin_fill.h"

namespace vscan::physics {

struct PartGeometry {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // centre of mass, part frame
  double mass_kg = 0.0;
  std::vector<Eigen::Vector3d> hull;  // hull points relative to the centre (the body frame)
  double radius = 0.0;                // largest |hull point|
  // kConvexDecomposition only: each piece's hull points relative to the centre; empty otherwise.
  std::vector<std::vector<Eigen::Vector3d>> pieces;
};

// The body frame is the part frame moved to the centre of mass: world_from_part =
// world_from_body * Translation(-centre).
PartGeometry MakePartGeometry(const PartType& part, int max_hull_vertices);

// The geometry of every part type; a convex decomposition is computed once per distinct mesh.
std::vector<PartGeometry> MakePartGeometries(const std::vector<PartType>& parts, int max_hull_vertices);

// The hull's vertices (exact, before reduction), relative to `centre`.
std::vector<Eigen::Vector3d> ExactHull(const TriangleMesh& mesh, const Eigen::Vector3d& centre);

// At most `count` of the points: the first farthest from their mean, then each the farthest from
// those kept (deterministic).
std::vector<Eigen::Vector3d> FarthestPoints(const std::vector<Eigen::Vector3d>& points, int count);

}  // namespace vscan::physics
