#pragma once
// A triangle mesh as a binary little-endian PLY file (vertex x y z, faces as vertex_indices), the
// form `vscan render` and mesh tools read.

#include <string>

#include "vscan/common/mesh.h"

namespace vscan::service {

std::string EncodeMeshPly(const TriangleMesh& mesh);

}  // namespace vscan::service
