#include "physics/convex_decomposition.h"

#include <HACD/hacdHACD.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <cstdlib>
#include <utility>

#include "physics/part_geometry.h"

namespace vscan::physics {
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
  for (size_t i = 0; i < n; ++i) volume[i] = HullVolume(pieces[i]);
  const auto added = [&](size_t i, size_t j) {
    std::vector<Eigen::Vector3d> both = pieces[i];
    both.insert(both.end(), pieces[j].begin(), pieces[j].end());
    return HullVolume(both) - volume[i] - volume[j];
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
    pieces[bi] = HullVertices(pieces[bi]);
    volume[bi] = HullVolume(pieces[bi]);
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

// HACD's clusters, merged while cheap, each simplified; the hull alone for a convex mesh.
std::vector<std::vector<Eigen::Vector3d>> ComputePieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                        double hull_tolerance_m) {
  const std::vector<Eigen::Vector3d> hull = ExactHull(mesh, centre);
  const double hull_volume = HullVolume(hull);
  // A mesh convex to within the hull's own tolerance is its hull, one piece, without HACD.
  if (ConvexWithin(mesh, centre, hull, hull_tolerance_m)) return {SimplifiedHull(hull, hull_tolerance_m)};
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
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  for (const auto& piece : Merged(std::move(raw), kMergeShare * hull_volume)) {
    pieces.push_back(SimplifiedHull(piece, hull_tolerance_m));
  }
  if (pieces.empty()) pieces.push_back(SimplifiedHull(hull, hull_tolerance_m));
  return pieces;
}

// FNV-1a over the mesh, the centre, the tolerance and the parameters above, from `basis`.
uint64_t HashOf(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double tolerance, uint64_t basis) {
  uint64_t h = basis;
  const auto add = [&](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  add(mesh.vertices.data(), mesh.vertices.size() * sizeof(mesh.vertices[0]));
  add(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
  add(centre.data(), 3 * sizeof(double));
  add(&tolerance, sizeof(tolerance));
  // What else decides the pieces: a change to any of these (or to this number) names other files.
  const double parameters[] = {kHacdScale, kHacdConcavity, kMergeShare, 2.0};
  add(parameters, sizeof parameters);
  return h;
}

struct PiecesCache {
  std::mutex mutex;
  std::map<uint64_t, std::pair<TriangleMesh, std::vector<std::vector<Eigen::Vector3d>>>> entries;
};

PiecesCache& Cache() {
  static PiecesCache cache;
  return cache;
}

constexpr size_t kCachedMeshes = 32;

struct StoreDirectory {
  std::mutex mutex;
  std::string path;
};

StoreDirectory& Directory() {
  static StoreDirectory directory;
  return directory;
}

}  // namespace

void SetDecompositionDirectory(std::string dir) {
  std::lock_guard lock(Directory().mutex);
  Directory().path = std::move(dir);
}

std::string DecompositionDirectory() {
  std::lock_guard lock(Directory().mutex);
  return Directory().path;
}

PiecesKey DecompositionKey(const TriangleMesh& mesh, const Eigen::Vector3d& centre, double hull_tolerance_m) {
  return {HashOf(mesh, centre, hull_tolerance_m, 1469598103934665603ull),
          HashOf(mesh, centre, hull_tolerance_m, 0x9e3779b97f4a7c15ull), mesh.vertices.size(), mesh.triangles.size()};
}

std::vector<std::vector<Eigen::Vector3d>> ConvexPieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                       double hull_tolerance_m) {
  const PiecesKey disk_key = DecompositionKey(mesh, centre, hull_tolerance_m);
  const uint64_t key = disk_key.name;
  {
    std::lock_guard lock(Cache().mutex);
    const auto it = Cache().entries.find(key);
    // The mesh itself is compared too: a hash collision must not hand out another part's pieces.
    if (it != Cache().entries.end() && it->second.first.vertices == mesh.vertices &&
        it->second.first.triangles == mesh.triangles) {
      return it->second.second;
    }
  }
  const std::string dir = DecompositionDirectory();
  std::optional<ConvexPieceSet> stored;
  if (!dir.empty()) stored = LoadPieces(dir, disk_key);
  auto pieces = stored ? std::move(*stored) : ComputePieces(mesh, centre, hull_tolerance_m);
  if (!dir.empty() && !stored) StorePieces(dir, disk_key, pieces);
  std::lock_guard lock(Cache().mutex);
  if (Cache().entries.size() >= kCachedMeshes) Cache().entries.erase(Cache().entries.begin());
  Cache().entries[key] = {mesh, pieces};
  return pieces;
}

}  // namespace vscan::physics
