#include "tote_mesh.h"

namespace vscan::physics::test {

TriangleMesh SlopedTote(float floor_x, float floor_y, float top_x, float top_y, float depth) {
  TriangleMesh mesh;
  const float fx = 0.5f * floor_x, fy = 0.5f * floor_y, tx = 0.5f * top_x, ty = 0.5f * top_y;
  // Floor corners 0..3 and rim corners 4..7, counter-clockwise seen from above.
  mesh.vertices = {{-fx, -fy, 0}, {fx, -fy, 0}, {fx, fy, 0}, {-fx, fy, 0},
                   {-tx, -ty, depth}, {tx, -ty, depth}, {tx, ty, depth}, {-tx, ty, depth}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  for (uint32_t k = 0; k < 4; ++k) {
    const uint32_t next = (k + 1) % 4;
    // Normals point into the tote.
    mesh.triangles.push_back({k, k + 4, next + 4});
    mesh.triangles.push_back({k, next + 4, next});
  }
  return mesh;
}

}  // namespace vscan::physics::test
