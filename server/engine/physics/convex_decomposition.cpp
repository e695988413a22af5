#include "physics/convex_decomposition.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <cstdlib>
#include <utility>

#include "physics/part_geometry.h"
#include "physics/plane_cut_decomposition.h"

namespace vscan::physics {
namespace {


// The hull alone for a mesh convex within the hull's tolerance; plane cuts otherwise.
std::vector<std::vector<Eigen::Vector3d>> ComputePieces(const TriangleMesh& mesh, const Eigen::Vector3d& centre,
                                                        double hull_tolerance_m) {
  const std::vector<Eigen::Vector3d> hull = ExactHull(mesh, centre);
  if (ConvexWithin(mesh, centre, hull, hull_tolerance_m)) return {SimplifiedHull(hull, hull_tolerance_m)};
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  PlaneCutOptions options;
  options.concavity_m = std::max(kDecompositionConcavityShare * static_cast<double>((hi - lo).maxCoeff()), hull_tolerance_m);
  options.max_pieces = kMaxDecompositionPieces;
  std::vector<std::vector<Eigen::Vector3d>> pieces;
  for (const auto& piece : PlaneCutPieces(mesh, centre, options)) pieces.push_back(SimplifiedHull(piece, hull_tolerance_m));
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
  const double parameters[] = {kDecompositionConcavityShare, static_cast<double>(kMaxDecompositionPieces), 3.0};
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
