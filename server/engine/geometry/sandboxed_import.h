#pragma once
// ImportMesh in a separate, resource-limited process (the vscan-mesh-import helper), so that
// an importer that aborts, hangs or runs out of memory on hostile input cannot take the caller
// down with it.

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include "geometry/mesh_import.h"

namespace vscan::geometry {

struct ImportSandbox {
  std::string helper_path;  // the vscan-mesh-import executable
  std::chrono::milliseconds timeout = std::chrono::seconds(60);
  // Address space of the helper; a 250 MB binary STL needs between 6 and 8 GiB of it.
  uint64_t memory_limit_bytes = uint64_t{8} << 30;
};

// ImportMesh's results and errors, plus: INVALID_ARGUMENT ("mesh data: ...") when the helper
// does not finish within the timeout or stops abnormally (it is killed and reaped either way),
// RESOURCE_EXHAUSTED when it runs out of memory, UNAVAILABLE ("mesh importer: cannot start
// ...") when it cannot be started. Safe to call from many threads at once.
StatusOr<TriangleMesh> ImportMeshIsolated(std::string_view bytes, MeshFileFormat format, double metres_per_unit,
                                          const ImportSandbox& options);

}  // namespace vscan::geometry
