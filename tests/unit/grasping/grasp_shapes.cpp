#include "grasp_shapes.h"

#include <cmath>
#include <numbers>

namespace vscan::grasping::testing {
namespace {

void Add(TriangleMesh& m, uint32_t a, uint32_t b, uint32_t c) { m.triangles.push_back({a, b, c}); }

uint32_t Vertex(TriangleMesh& m, double x, double y, double z) {
  m.vertices.emplace_back(float(x), float(y), float(z));
  return uint32_t(m.vertices.size() - 1);
}

}  // namespace

TriangleMesh MakeCylinder(double radius, double height, int segments) {
  TriangleMesh m;
  const uint32_t bottom = Vertex(m, 0, 0, 0), top = Vertex(m, 0, 0, height);
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * std::numbers::pi * i / segments;
    Vertex(m, radius * std::cos(a), radius * std::sin(a), 0);
    Vertex(m, radius * std::cos(a), radius * std::sin(a), height);
  }
  for (int i = 0; i < segments; ++i) {
    const uint32_t b0 = 2 + 2 * i, t0 = b0 + 1, b1 = 2 + 2 * ((i + 1) % segments), t1 = b1 + 1;
    Add(m, bottom, b1, b0);
    Add(m, top, t0, t1);
    Add(m, b0, b1, t1);
    Add(m, b0, t1, t0);
  }
  return m;
}

TriangleMesh MakePlateWithHole(double half, double hole_half, double thickness) {
  TriangleMesh m;
  const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};  // counter-clockwise from +z
  uint32_t ob[4], ot[4], ib[4], it[4];
  for (int i = 0; i < 4; ++i) {
    ob[i] = Vertex(m, half * corners[i][0], half * corners[i][1], 0);
    ot[i] = Vertex(m, half * corners[i][0], half * corners[i][1], thickness);
    ib[i] = Vertex(m, hole_half * corners[i][0], hole_half * corners[i][1], 0);
    it[i] = Vertex(m, hole_half * corners[i][0], hole_half * corners[i][1], thickness);
  }
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    Add(m, ot[i], ot[j], it[j]);  // top ring, facing +z
    Add(m, ot[i], it[j], it[i]);
    Add(m, ob[i], ib[j], ob[j]);  // bottom ring, facing -z
    Add(m, ob[i], ib[i], ib[j]);
    Add(m, ob[i], ob[j], ot[j]);  // outer wall, facing out
    Add(m, ob[i], ot[j], ot[i]);
    Add(m, ib[i], it[j], ib[j]);  // hole wall, facing the hole's axis
    Add(m, ib[i], it[i], it[j]);
  }
  return m;
}

TriangleMesh Flipped(TriangleMesh mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

TriangleMesh Join(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const auto offset = uint32_t(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles) m.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return m;
}

}  // namespace vscan::grasping::testing
