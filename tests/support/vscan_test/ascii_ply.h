#pragma once
// Reads the vertices and faces of an ASCII PLY file, independently of the importers under test.

#include <string>

#include "vscan/common/mesh.h"

namespace vscan::test {

// Extra vertex properties are skipped and polygons fanned into triangles; fails the calling test
// (and returns an empty mesh) when the file cannot be read.
TriangleMesh ReadAsciiPly(const std::string& path);

}  // namespace vscan::test
