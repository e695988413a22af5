#include "vscan_test/meshes.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace vscan::test {

TriangleMesh MakeSquare(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double half_size) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = n.cross(helper).normalized() * half_size;
  const Eigen::Vector3d e2 = n.cross(e1).normalized() * half_size;
  TriangleMesh mesh;
  const Eigen::Vector3d corners[4] = {centre - e1 - e2, centre + e1 - e2, centre + e1 + e2, centre - e1 + e2};
  for (const Eigen::Vector3d& corner : corners) mesh.vertices.push_back(corner.cast<float>());
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh MakeGrid(double half_side, int cells) {
  TriangleMesh mesh;
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      mesh.vertices.emplace_back(static_cast<float>(half_side * (2.0 * i / cells - 1)),
                                 static_cast<float>(half_side * (2.0 * j / cells - 1)), 0.0f);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

TriangleMesh MakeUvSphere(double radius, int rings, int segments) {
  TriangleMesh mesh;
  for (int r = 0; r <= rings; ++r) {
    const double polar = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2 * std::numbers::pi * s / segments;
      const Eigen::Vector3d unit(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                 std::cos(polar));
      mesh.vertices.emplace_back(unit.cast<float>() * static_cast<float>(radius));
    }
  }
  const auto at = [&](int r, int s) { return static_cast<uint32_t>(r * segments + (s % segments)); };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      if (r > 0) mesh.triangles.push_back({at(r, s), at(r + 1, s), at(r, s + 1)});
      if (r + 1 < rings) mesh.triangles.push_back({at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
    }
  }
  return mesh;
}

TriangleMesh MakeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back(static_cast<float>(i & 1 ? hi.x() : lo.x()), static_cast<float>(i & 2 ? hi.y() : lo.y()),
                               static_cast<float>(i & 4 ? hi.z() : lo.z()));
  }
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

}  // namespace vscan::test
