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
// Hulls and pieces are simplified within hull_tolerance_m (SimplifiedHull).
PartGeometry MakePartGeometry(const PartType& part, double hull_tolerance_m);

// The geometry of every part type; a convex decomposition is computed once per distinct mesh.
std::vector<PartGeometry> MakePartGeometries(const std::vector<PartType>& parts, double hull_tolerance_m);

// The hull's vertices (exact, before reduction), relative to `centre`.
std::vector<Eigen::Vector3d> ExactHull(const TriangleMesh& mesh, const Eigen::Vector3d& centre);

// At most `count` of the points: the first farthest from their mean, then each the farthest from
// those kept (deterministic).
std::vector<Eigen::Vector3d> FarthestPoints(const std::vector<Eigen::Vector3d>& points, int count);

// A subset of the points whose hull holds every point within `tolerance` (Euclidean distance to
// that hull): from four farthest points, the point farthest outside is added until none lies
// farther than the tolerance. All the points when they need all. Deterministic.
std::vector<Eigen::Vector3d> SimplifiedHull(const std::vector<Eigen::Vector3d>& points, double tolerance);

// Whether a closed mesh is convex to within `tolerance` (metres): none of its vertices and
// triangle centroids lies deeper than that under the surface of its hull (`hull`, relative to
// `centre`, as ExactHull gives it), and the hull encloses at most `tolerance` times its area more
// than the mesh. Cheap: linear in the mesh's size times the hull's faces.
bool ConvexWithin(const TriangleMesh& mesh, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& hull,
                  double tolerance);

// The volume of the points' convex hull (0 when flat), and the volume a closed mesh encloses.
double HullVolume(const std::vector<Eigen::Vector3d>& points);
double MeshVolume(const TriangleMesh& mesh);

// A face of a convex hull: its corners in order and its outward unit normal; inside is
// normal . x <= offset.
struct HullFace {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0.0;
  std::vector<Eigen::Vector3d> corners;
};

// The faces of the points' convex hull (none, or fewer than four, when the points are flat).
std::vector<HullFace> HullFaces(const std::vector<Eigen::Vector3d>& points);

// The vertices of the points' convex hull (all of them when flat).
std::vector<Eigen::Vector3d> HullVertices(const std::vector<Eigen::Vector3d>& points);

// How far the point lies outside the hull of `hull` (0 inside); the hull must span a volume.
double DistanceOutsideHull(const Eigen::Vector3d& point, const std::vector<Eigen::Vector3d>& hull);

}  // namespace vscan::physics
