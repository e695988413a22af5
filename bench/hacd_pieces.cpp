#include "hacd_pieces.h"

#include <HACD/hacdHACD.h>

#include <algorithm>

#include "physics/part_geometry.h"

namespace vscan::bench {
namespace {

// HACD works on the mesh scaled into a cube of this size; concavity is in the same units.
constexpr double kHacdScale = 1000.0;
// Deepest concavity a piece may keep: 2% of the part's size.
constexpr double kHacdConcavity = 20.0;

// Two pieces merge while their union's hull adds at most this share of the part's hull volume to
// theirs: HACD leaves many slivers on a mesh whose triangles do not share edges, and a compound's
// cost grows with its pieces squared.
constexpr double kMergeShare = 0.03;

std::vector<std::vector<Eigen::Vector3d>> Merged(std::vector<std::vector<Eigen::Vector3d>> pieces, double limit) {
  const size_t n = pieces.size();
  std::vector<double> volume(n);
  for (size_t i = 0; i < n; ++i) volume[i] = physics::HullVolume(pieces[i]);
  const auto added = [&](size_t i, size_t j) {
    std::vector<Eigen::Vector3d> both = pieces[i];
    both.insert(both.end(), pieces[j].begin(), pieces[j].end());
    return physics::HullVolume(both) - volume[i] - volume[j];
  };
  std::vector<std::vector<double>> cost(n, std::vector<double>(n, 0.0));
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) cost[i][j] = added(i, j);
  }
  std::vector<bool> alive(n, true);
  for (;;) {
    size_t bi = n, bj = n;
    double best = limit;
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = i + 1; j < n && alive[i]; ++j) {
        if (alive[j] && cost[i][j] <= best) best = cost[i][j], bi = i, bj = j;
      }
    }
    if (bi == n) break;
    pieces[bi].insert(pieces[bi].end(), pieces[bj].begin(), pieces[bj].end());
    pieces[bi] = physics::HullVertices(pieces[bi]);
    volume[bi] = physics::HullVolume(pieces[bi]);
    alive[bj] = false;
    for (size_t k = 0; k < n; ++k) {
      if (!alive[k] || k == bi) continue;
      (k < bi ? cost[k][bi] : cost[bi][k]) = added(std::min(k, bi), std::max(k, bi));
    }
  }
  std::vector<std::vector<Eigen::Vector3d>> out;
  for (size_t i = 0; i < n; ++i) {
    if (alive[i]) out.push_back(std::move(pieces[i]));
  }
  return out;
}

}  // namespace

std::vector<std::vector<Eigen::Vector3d>> HacdPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre) {
  const double hull_volume = physics::HullVolume(physics::ExactHull(mesh, centre));
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
  // Concavity at points cast from the faces (without them an L comes back whole), not at HACD's
  // extra distance points: those cost most of its time and split a tube's wall into slivers.
  hacd.SetAddExtraDistPoints(false);
  hacd.SetAddFacesPoints(true);

  std::vector<std::vector<Eigen::Vector3d>> raw;
  if (!triangles.empty() && hacd.Compute()) {
    for (size_t c = 0; c < hacd.GetNClusters(); ++c) {
      std::vector<HACD::Vec3<HACD::Real>> hull_points(hacd.GetNPointsCH(c));
      std::vector<HACD::Vec3<long>> hull_triangles(hacd.GetNTrianglesCH(c));
      if (hull_points.size() < 4 || !hacd.GetCH(c, hull_points.data(), hull_triangles.data())) continue;
      std::vector<Eigen::Vector3d> piece;
      piece.reserve(hull_points.size());
      for (const auto& p : hull_points) piece.push_back(Eigen::Vector3d(p.X(), p.Y(), p.Z()) - centre);
      raw.push_back(std::move(piece));
    }
  }
  return Merged(std::move(raw), kMergeShare * hull_volume);
}


}  // namespace vscan::bench
