#include "machined_parts.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace vscan::physics::test {

TriangleMesh Riser() {
  constexpr double kStep = 0.001, kLengthX = 0.040, kLengthY = 0.030, kBase = 0.012;
  const int nx = static_cast<int>(std::lround(kLengthX / kStep)) + 1;
  const int ny = static_cast<int>(std::lround(kLengthY / kStep)) + 1;
  const auto height = [&](double x, double y) {
    for (double bx : {-0.010, 0.010}) {
      // Crowned tops: every grid point of a boss's top is a corner of the hull.
      const double r = std::hypot(x - bx, y);
      if (r <= 0.006) return kBase + 0.005 + 0.001 * (1 - r * r / 0.000036);
    }
    if (std::abs(x) <= 0.004 && std::abs(std::abs(y) - 0.0095) <= 0.003) return kBase - 0.004;
    return kBase;
  };
  TriangleMesh mesh;
  const auto index = [&](int i, int j, int layer) { return static_cast<uint32_t>(layer * nx * ny + j * nx + i); };
  for (int layer = 0; layer < 2; ++layer) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const double x = -0.5 * kLengthX + i * kStep, y = -0.5 * kLengthY + j * kStep;
        mesh.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                   static_cast<float>(layer == 0 ? 0.0 : height(x, y)));
      }
    }
  }
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      // Top faces up, bottom faces down.
      mesh.triangles.push_back({index(i, j, 1), index(i + 1, j, 1), index(i + 1, j + 1, 1)});
      mesh.triangles.push_back({index(i, j, 1), index(i + 1, j + 1, 1), index(i, j + 1, 1)});
      mesh.triangles.push_back({index(i, j, 0), index(i + 1, j + 1, 0), index(i + 1, j, 0)});
      mesh.triangles.push_back({index(i, j, 0), index(i, j + 1, 0), index(i + 1, j + 1, 0)});
    }
  }
  // The boundary counter-clockwise seen from above, each step joined top to bottom facing out.
  std::vector<std::pair<int, int>> ring;
  for (int i = 0; i + 1 < nx; ++i) ring.emplace_back(i, 0);
  for (int j = 0; j + 1 < ny; ++j) ring.emplace_back(nx - 1, j);
  for (int i = nx - 1; i > 0; --i) ring.emplace_back(i, ny - 1);
  for (int j = ny - 1; j > 0; --j) ring.emplace_back(0, j);
  for (size_t k = 0; k < ring.size(); ++k) {
    const auto [i0, j0] = ring[k];
    const auto [i1, j1] = ring[(k + 1) % ring.size()];
    mesh.triangles.push_back({index(i0, j0, 0), index(i1, j1, 0), index(i1, j1, 1)});
    mesh.triangles.push_back({index(i0, j0, 0), index(i1, j1, 1), index(i0, j0, 1)});
  }
  return mesh;
}

TriangleMesh ManySidedPrism(int sides, double radius, double height) {
  TriangleMesh mesh;
  for (int layer = 0; layer < 2; ++layer) {
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * M_PI * k / sides;
      mesh.vertices.emplace_back(static_cast<float>(radius * std::cos(a)), static_cast<float>(radius * std::sin(a)),
                                 static_cast<float>(layer * height));
    }
  }
  const auto n = static_cast<uint32_t>(sides);
  const uint32_t bottom = 2 * n, top = 2 * n + 1;
  mesh.vertices.emplace_back(0.0f, 0.0f, 0.0f);
  mesh.vertices.emplace_back(0.0f, 0.0f, static_cast<float>(height));
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t next = (k + 1) % n;
    mesh.triangles.push_back({bottom, next, k});
    mesh.triangles.push_back({top, n + k, n + next});
    mesh.triangles.push_back({k, next, n + next});
    mesh.triangles.push_back({k, n + next, n + k});
  }
  return mesh;
}

TriangleMesh Torus(int n) {
  const int m = n / 2;
  TriangleMesh mesh;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m, r = 0.05 + 0.02 * std::cos(v);
      mesh.vertices.emplace_back(float(r * std::cos(u)), float(r * std::sin(u)), float(0.02 * std::sin(v)));
    }
  }
  const auto at = [&](int a, int b) { return uint32_t((a % n) * m + b % m); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return mesh;
}

}  // namespace vscan::physics::test
