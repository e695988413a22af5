#include "test_meshes.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

namespace vscan::test {
namespace {

Eigen::Vector3f ToFloat(const Eigen::Vector3d& v) { return v.cast<float>(); }

// Index of the vertex halfway between a and b on the unit sphere, created once per edge.
uint32_t Midpoint(uint32_t a, uint32_t b, std::vector<Eigen::Vector3d>& unit,
                  std::map<std::pair<uint32_t, uint32_t>, uint32_t>& cache) {
  const auto key = std::minmax(a, b);
  const auto found = cache.find(key);
  if (found != cache.end()) return found->second;
  unit.push_back((unit[a] + unit[b]).normalized());
  const auto index = static_cast<uint32_t>(unit.size() - 1);
  cache.emplace(key, index);
  return index;
}

}  // namespace

TriangleMesh MakeSquare(const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double half_size) {
  const Eigen::Vector3d n = normal.normalized();
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = n.cross(helper).normalized() * half_size;
  const Eigen::Vector3d e2 = n.cross(e1).normalized() * half_size;
  TriangleMesh mesh;
  mesh.vertices = {ToFloat(centre - e1 - e2), ToFloat(centre + e1 - e2), ToFloat(centre + e1 + e2),
                   ToFloat(centre - e1 + e2)};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh MakeIcosphere(const Eigen::Vector3d& centre, double radius, int levels) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> unit = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                       {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& v : unit) v.normalize();
  std::vector<std::array<uint32_t, 3>> faces = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> cache;
    std::vector<std::array<uint32_t, 3>> finer;
    finer.reserve(4 * faces.size());
    for (const auto& f : faces) {
      const uint32_t ab = Midpoint(f[0], f[1], unit, cache);
      const uint32_t bc = Midpoint(f[1], f[2], unit, cache);
      const uint32_t ca = Midpoint(f[2], f[0], unit, cache);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  TriangleMesh mesh;
  for (const auto& v : unit) mesh.vertices.push_back(ToFloat(centre + radius * v));
  mesh.triangles = std::move(faces);
  return mesh;
}

TriangleMesh ReadAsciiPly(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  size_t vertices = 0, faces = 0, vertex_properties = 0;
  std::string line, element;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "element") {
      size_t n = 0;
      words >> element >> n;
      if (element == "vertex") vertices = n;
      if (element == "face") faces = n;
    }
    if (key == "property" && element == "vertex") ++vertex_properties;
    if (key == "end_header") break;
  }
  TriangleMesh mesh;
  mesh.vertices.resize(vertices);
  for (auto& v : mesh.vertices) {
    in >> v.x() >> v.y() >> v.z();
    for (size_t k = 3; k < vertex_properties; ++k) {
      float ignored;
      in >> ignored;
    }
  }
  for (size_t f = 0; f < faces; ++f) {
    size_t n = 0;
    in >> n;
    std::vector<uint32_t> ids(n);
    for (auto& id : ids) in >> id;
    for (size_t k = 1; k + 1 < n; ++k) mesh.triangles.push_back({ids[0], ids[k], ids[k + 1]});
  }
  EXPECT_TRUE(static_cast<bool>(in)) << path << ": truncated PLY body";
  if (!in) return {};
  return mesh;
}

double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  // Finds the closest point by the Voronoi region of the triangle p falls in.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  }
  const double scale = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * scale) + ac * (vc * scale))).norm();
}

double DistanceToMesh(const Eigen::Vector3d& p, const TriangleMesh& mesh) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    best = std::min(best, PointTriangleDistance(p, mesh.vertices[t[0]].cast<double>(),
                                                mesh.vertices[t[1]].cast<double>(),
                                                mesh.vertices[t[2]].cast<double>()));
  }
  return best;
}

}  // namespace vscan::test
