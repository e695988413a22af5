#include "service/model/model_mesh_ply.h"

#include <bit>
#include <cstdint>
#include <cstring>

namespace vscan::service {
namespace {

static_assert(std::endian::native == std::endian::little, "PLY bytes are written as the machine holds them");

template <typename T>
void Append(std::string& out, const T& value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::string EncodeMeshPly(const TriangleMesh& mesh) {
  // Each vertex leads with a one-byte property of value 1: assimp's header reader (what `vscan
  // render` reads meshes with) swallows a first data byte that looks like a line end, and a float
  // such as 0.0f or -0.04f begins with one. Other readers skip the unknown property.
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment vscan mesh, model frame, metres\nelement vertex " +
                    std::to_string(mesh.vertices.size()) +
                    "\nproperty uchar vscan\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + mesh.vertices.size() * 13 + mesh.triangles.size() * 13);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    Append(out, uint8_t{1});
    Append(out, v.x());
    Append(out, v.y());
    Append(out, v.z());
  }
  for (const auto& t : mesh.triangles) {
    Append(out, uint8_t{3});
    for (const uint32_t i : t) Append(out, static_cast<int32_t>(i));
  }
  return out;
}

}  // namespace vscan::service
