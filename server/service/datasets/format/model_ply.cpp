#include "service/datasets/format/model_ply.h"

#include <bit>
#include <cstring>

#include "service/datasets/format/dataset_layout.h"
#include "service/datasets/format/bop_units.h"

namespace vscan::service::dataset {
namespace {

// Little-endian bytes of a 4-byte value (x86 and ARM hosts are little-endian; checked at compile time).
template <typename T>
void Append(std::string& out, T value) {
  static_assert(sizeof(T) == 4);
  static_assert(std::endian::native == std::endian::little);
  char bytes[4];
  std::memcpy(bytes, &value, 4);
  out.append(bytes, 4);
}

}  // namespace

std::string ModelPlyPath(uint32_t obj_id) { return std::string(kModelsDir) + "/obj_" + SixDigits(obj_id) + ".ply"; }

StatusOr<std::string> EncodeModelPly(const PartModel& part) {
  const std::string field = "parts[obj_id " + std::to_string(part.obj_id) + "].mesh";
  const TriangleMesh& mesh = part.mesh;
  if (mesh.empty()) return InvalidArgument(field, "has no triangles");
  for (const auto& triangle : mesh.triangles) {
    for (const uint32_t index : triangle) {
      if (index >= mesh.vertices.size()) {
        return InvalidArgument(field, "a triangle indexes vertex " + std::to_string(index) + " of " +
                                          std::to_string(mesh.vertices.size()));
      }
    }
  }
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment vscan part, millimetres\nelement vertex " +
                    std::to_string(mesh.vertices.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  out.reserve(out.size() + mesh.vertices.size() * 12 + mesh.triangles.size() * 13);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    for (int axis = 0; axis < 3; ++axis) Append(out, v[axis] * static_cast<float>(kMillimetresPerMetre));
  }
  for (const auto& triangle : mesh.triangles) {
    out.push_back(char(3));
    for (const uint32_t index : triangle) Append(out, int32_t(index));
  }
  return out;
}

}  // namespace vscan::service::dataset
