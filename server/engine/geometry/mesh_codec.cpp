// EncodeMesh / DecodeMesh: "VSMESH01", uint64 vertex count, uint64 triangle count,
// float32 xyz per vertex, uint32 index triples; all little-endian.

#include <bit>
#include <cmath>
#include <cstring>

#include "geometry/mesh_import.h"
#include "geometry/little_endian.h"

namespace vscan::geometry {
namespace {

constexpr std::string_view kMeshMagic = "VSMESH01";
constexpr size_t kHeaderSize = 8 + 8 + 8;
constexpr size_t kVertexSize = 3 * 4;
constexpr size_t kTriangleSize = 3 * 4;

}  // namespace

std::string EncodeMesh(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(kHeaderSize + kVertexSize * mesh.vertices.size() + kTriangleSize * mesh.triangles.size());
  out.append(kMeshMagic);
  PutLe(out, mesh.vertices.size(), 8);
  PutLe(out, mesh.triangles.size(), 8);
  for (const auto& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i) PutLe(out, std::bit_cast<uint32_t>(v[i]), 4);
  }
  for (const auto& t : mesh.triangles) {
    for (uint32_t index : t) PutLe(out, index, 4);
  }
  return out;
}

StatusOr<TriangleMesh> DecodeMesh(std::string_view bytes) {
  if (bytes.size() < kHeaderSize || bytes.substr(0, kMeshMagic.size()) != kMeshMagic) {
    return DataLoss("mesh blob: missing VSMESH01 header");
  }
  uint64_t vertex_count = GetLe(bytes.data() + 8, 8);
  uint64_t triangle_count = GetLe(bytes.data() + 16, 8);
  size_t payload = bytes.size() - kHeaderSize;
  // Bounded before multiplying so that absurd counts cannot overflow the size check.
  if (vertex_count > payload / kVertexSize || triangle_count > payload / kTriangleSize ||
      vertex_count * kVertexSize + triangle_count * kTriangleSize != payload) {
    return DataLoss("mesh blob: " + std::to_string(bytes.size()) + " bytes do not hold " +
                    std::to_string(vertex_count) + " vertices and " + std::to_string(triangle_count) + " triangles");
  }

  TriangleMesh mesh;
  mesh.vertices.resize(vertex_count);
  mesh.triangles.resize(triangle_count);
  const char* in = bytes.data() + kHeaderSize;
  for (auto& v : mesh.vertices) {
    for (int i = 0; i < 3; ++i, in += 4) v[i] = std::bit_cast<float>(static_cast<uint32_t>(GetLe(in, 4)));
    if (!v.allFinite()) return DataLoss("mesh blob: non-finite vertex");
  }
  for (auto& t : mesh.triangles) {
    for (auto& index : t) {
      index = static_cast<uint32_t>(GetLe(in, 4));
      in += 4;
      if (index >= vertex_count) return DataLoss("mesh blob: triangle index out of range");
    }
  }
  return mesh;
}

}  // namespace vscan::geometry
