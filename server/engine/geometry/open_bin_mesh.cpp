#include "geometry/open_bin_mesh.h"

#include <array>

namespace vscan::geometry {
namespace {

// An axis-aligned box as 8 vertices and 12 outward-facing triangles.
void AppendBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half, TriangleMesh& mesh) {
  const auto base = static_cast<uint32_t>(mesh.vertices.size());
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d sign(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
    mesh.vertices.push_back((centre + sign.cwiseProduct(half)).cast<float>());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  static constexpr std::array<std::array<uint32_t, 3>, 12> kFaces = {{
      {0, 2, 1}, {1, 2, 3},  // z-
      {4, 5, 6}, {5, 7, 6},  // z+
      {0, 1, 4}, {1, 5, 4},  // y-
      {2, 6, 3}, {3, 6, 7},  // y+
      {0, 4, 2}, {2, 4, 6},  // x-
      {1, 3, 5}, {3, 7, 5},  // x+
  }};
  for (const auto& face : kFaces) mesh.triangles.push_back({base + face[0], base + face[1], base + face[2]});
}

}  // namespace

TriangleMesh OpenBinMesh(const Eigen::Vector3d& inner_size, double wall_thickness) {
  const double sx = inner_size.x(), sy = inner_size.y(), sz = inner_size.z(), w = wall_thickness;
  TriangleMesh mesh;
  AppendBox({0, 0, -0.5 * w}, {0.5 * sx + w, 0.5 * sy + w, 0.5 * w}, mesh);
  // The walls along y reach over the corners, so that no seam opens between walls.
  AppendBox({0.5 * (sx + w), 0, 0.5 * sz}, {0.5 * w, 0.5 * sy + w, 0.5 * sz}, mesh);
  AppendBox({-0.5 * (sx + w), 0, 0.5 * sz}, {0.5 * w, 0.5 * sy + w, 0.5 * sz}, mesh);
  AppendBox({0, 0.5 * (sy + w), 0.5 * sz}, {0.5 * sx, 0.5 * w, 0.5 * sz}, mesh);
  AppendBox({0, -0.5 * (sy + w), 0.5 * sz}, {0.5 * sx, 0.5 * w, 0.5 * sz}, mesh);
  return mesh;
}

}  // namespace vscan::geometry
