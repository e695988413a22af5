#pragma once
// Convex pieces kept on disk between processes: a dataset's shards, and later runs, of the same
// parts skip the cuts. One file a mesh, named by a hash of the mesh and the parameters and checked
// against a second, independent hash and the mesh's size.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace vscan::physics {

using ConvexPieceSet = std::vector<std::vector<Eigen::Vector3d>>;

// Two independent 64-bit hashes of a mesh and everything its pieces depend on, and its size.
struct PiecesKey {
  uint64_t name = 0;
  uint64_t check = 0;
  uint64_t vertices = 0;
  uint64_t triangles = 0;
};

// The pieces stored under `key` in `dir`, or nothing (no file, another mesh's, or unreadable).
std::optional<ConvexPieceSet> LoadPieces(const std::string& dir, const PiecesKey& key);

// Writes the pieces under `key` (a temporary file renamed into place, so that processes sharing
// the directory never read half a file); false when it could not.
bool StorePieces(const std::string& dir, const PiecesKey& key, const ConvexPieceSet& pieces);

}  // namespace vscan::physics
