#pragma once
// Mesh files (PLY, OBJ, STL via assimp) to TriangleMesh in metres, and our compact stored form.

#include <cstdint>
#include <string>
#include <string_view>

#include "vscan/common/mesh.h"
#include "vscan/common/status.h"

namespace vscan::geometry {

enum class MeshFileFormat { kAuto, kPly, kObj, kStl };

inline constexpr uint64_t kMaxImportTriangles = 50'000'000;

// Parses bytes of a mesh file; every vertex is multiplied by metres_per_unit (unit and scale).
// Rejects empty, malformed and non-finite meshes with INVALID_ARGUMENT naming "mesh data", and
// more than max_triangles triangles with RESOURCE_EXHAUSTED. Never reads other files (an OBJ's
// mtllib is ignored). Drops degenerate triangles and merges vertices with equal coordinates.
// A metres_per_unit that is not finite and positive is INVALID_ARGUMENT naming "scale".
StatusOr<TriangleMesh> ImportMesh(std::string_view bytes, MeshFileFormat format, double metres_per_unit,
                                  uint64_t max_triangles = kMaxImportTriangles);

// Versioned little-endian binary encoding of a mesh, used by the blob store.
std::string EncodeMesh(const TriangleMesh& mesh);
// DATA_LOSS unless bytes are exactly one well-formed encoding with in-range indices.
StatusOr<TriangleMesh> DecodeMesh(std::string_view bytes);

}  // namespace vscan::geometry
