// libFuzzer target for ImportMesh and the stored mesh codec. The first byte picks the format
// hint; the rest is the file. Any accepted mesh must be well formed and survive a codec round trip.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "geometry/mesh_import.h"

namespace {

using vscan::TriangleMesh;
using vscan::geometry::MeshFileFormat;

void Check(bool condition) {
  if (!condition) std::abort();
}

void CheckWellFormed(const TriangleMesh& mesh) {
  Check(!mesh.triangles.empty());
  for (const auto& v : mesh.vertices) Check(v.allFinite());
  for (const auto& t : mesh.triangles) {
    for (uint32_t index : t) Check(index < mesh.vertices.size());
    Check(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
  }
}

}  // namespace

// assimp 5.2 leaks a little on some error paths; report only leaks that do not pass through it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  constexpr MeshFileFormat kFormats[] = {MeshFileFormat::kAuto, MeshFileFormat::kPly, MeshFileFormat::kObj,
                                         MeshFileFormat::kStl};
  MeshFileFormat format = kFormats[data[0] % 4];
  std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);

  // Decoding arbitrary bytes must fail cleanly too.
  (void)vscan::geometry::DecodeMesh(bytes);

  // Keep inputs from asking for more triangles than a fuzzing run can hold.
  auto mesh = vscan::geometry::ImportMesh(bytes, format, 0.001, 1'000'000);
  if (!mesh.ok()) return 0;
  CheckWellFormed(*mesh);
  auto decoded = vscan::geometry::DecodeMesh(vscan::geometry::EncodeMesh(*mesh));
  Check(decoded.ok());
  Check(decoded->vertices == mesh->vertices && decoded->triangles == mesh->triangles);
  return 0;
}
