#include "physics/convex_decomposition.h"

#include <HACD/hacdHACD.h>

#include <algorithm>

#include "physics/part_geometry.h"

namespace vscan::physics {
namespace {

// HACD works on the mesh scaled into a cube of this size; concavity is in the same units.
constexpr double kHacdScale = 1000.0;
// Deepest concavity a piece may keep: 2% of the part's size.
constexpr double kHacdConcavity = 20.0;

}  // namespace

std::vector<std::vector<Eigen::Vector3d>> ConvexPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                       double hull_tolerance_m) {
  std::vector<HACD::Vec3<HACD::Real>> points;
  points.reserve(mesh.vertices.size());
  for (const Eigen::Vector3f& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<HACD::Vec3<long>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    triangles.emplace_back(static_cast<long>(t[0]), static_cast<long>(t[1]), static_cast<long>(t[2]));
  }
  HACD::HACD hacd;
  hacd.SetPoints(points.data());
  hacd.SetNPoints(points.size());
  hacd.SetTriangles(triangles.data());
  hacd.SetNTriangles(triangles.size());
  hacd.SetScaleFactor(kHacdScale);
  hacd.SetConcavity(kHacdConcavity);
  hacd.SetNClusters(1);
  hacd.SetCompacityWeight(0.1);
  hacd.SetVolumeWeight(0.0);
  hacd.SetNVerticesPerCH(1000);  // SimplifiedHull reduces each piece, by distance
  hacd.SetAddExtraDistPoints(true);
  hacd.SetAddFacesPoints(true);

  std::vector<std::vector<Eigen::Vector3d>> pieces;
  if (!triangles.empty() && hacd.Compute()) {
    for (size_t c = 0; c < hacd.GetNClusters(); ++c) {
      std::vector<HACD::Vec3<HACD::Real>> hull_points(hacd.GetNPointsCH(c));
      std::vector<HACD::Vec3<long>> hull_triangles(hacd.GetNTrianglesCH(c));
      if (hull_points.size() < 4 || !hacd.GetCH(c, hull_points.data(), hull_triangles.data())) continue;
      std::vector<Eigen::Vector3d> piece;
      piece.reserve(hull_points.size());
      for (const auto& p : hull_points) piece.push_back(Eigen::Vector3d(p.X(), p.Y(), p.Z()) - centre);
      pieces.push_back(SimplifiedHull(piece, hull_tolerance_m));
    }
  }
  if (pieces.empty()) pieces.push_back(SimplifiedHull(ExactHull(mesh, centre), hull_tolerance_m));
  return pieces;
}

}  // namespace vscan::physics
