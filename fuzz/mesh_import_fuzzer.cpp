// libFuzzer target for a mesh upload as the vscan-mesh-import helper and vscand see it. The first
// byte picks the format the client named; the rest is the file. The helper imports it and encodes
// its result (EncodeImportResult); vscand parses that result (ParseImportResult), which must give
// back exactly the mesh or the error the helper had. The raw input also goes through the parsers of
// the helper's output and of a stored mesh, which must refuse what they cannot read without harm.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "geometry/import_protocol.h"
#include "geometry/mesh_import.h"

namespace {

using vscan::StatusCode;
using vscan::TriangleMesh;
using vscan::geometry::MeshFileFormat;

void Check(bool condition, const char* what) {
  if (condition) return;
  std::fprintf(stderr, "mesh_import_fuzzer: %s\n", what);
  std::abort();
}

void CheckWellFormed(const TriangleMesh& mesh) {
  Check(!mesh.triangles.empty(), "accepted mesh without triangles");
  for (const auto& v : mesh.vertices) Check(v.allFinite(), "accepted mesh with a non-finite vertex");
  for (const auto& t : mesh.triangles) {
    for (uint32_t index : t) Check(index < mesh.vertices.size(), "triangle index out of range");
    Check(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "degenerate triangle kept");
  }
}

// A refusal the client can act on; INTERNAL or UNKNOWN would mean the importer lost its way.
void CheckRefusal(StatusCode code) {
  Check(code == StatusCode::kInvalidArgument || code == StatusCode::kResourceExhausted,
        "import refused with a code other than INVALID_ARGUMENT or RESOURCE_EXHAUSTED");
}

}  // namespace

// assimp 5.2 leaks a little on some error paths; report only leaks that do not pass through it.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  constexpr MeshFileFormat kFormats[] = {MeshFileFormat::kAuto, MeshFileFormat::kPly, MeshFileFormat::kObj,
                                         MeshFileFormat::kStl};
  const MeshFileFormat format = kFormats[data[0] % 4];
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);

  // What a stored blob or a misbehaving helper could hold must fail cleanly.
  (void)vscan::geometry::DecodeMesh(bytes);
  (void)vscan::geometry::ParseImportResult(bytes);

  // Keep inputs from asking for more triangles than a fuzzing run can hold.
  const auto mesh = vscan::geometry::ImportMesh(bytes, format, 0.001, 1'000'000);
  const vscan::geometry::EncodedImportResult encoded = vscan::geometry::EncodeImportResult(mesh);
  const auto received = vscan::geometry::ParseImportResult(encoded.header + encoded.payload);
  if (!mesh.ok()) {
    CheckRefusal(mesh.status().code());
    Check(received.status().code() == mesh.status().code(), "the helper's error code changed on the way");
    Check(received.status().message() == mesh.status().message(), "the helper's message changed on the way");
    return 0;
  }
  CheckWellFormed(*mesh);
  Check(received.ok(), "vscand refused the helper's mesh");
  Check(received->vertices == mesh->vertices && received->triangles == mesh->triangles,
        "the mesh changed on the way from the helper");
  return 0;
}
