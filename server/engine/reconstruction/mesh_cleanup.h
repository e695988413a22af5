#pragma once
// Mesh clean-up after surface extraction: small disconnected pieces, unused vertices.

#include <cstddef>
#include <vector>

#include "vscan/common/mesh.h"

namespace vscan::reconstruction {

// Drops the connected components (triangles sharing vertices) with fewer than min_triangles
// triangles, then the vertices no triangle uses. Returns how many triangles were dropped.
size_t RemoveSmallComponents(TriangleMesh& mesh, size_t min_triangles);

// Keeps the triangles whose three vertices are all marked, then drops unused vertices.
void KeepTrianglesOnVertices(TriangleMesh& mesh, const std::vector<bool>& keep_vertex);

// Drops vertices no triangle uses, renumbering the triangles.
void DropUnusedVertices(TriangleMesh& mesh);

}  // namespace vscan::reconstruction
