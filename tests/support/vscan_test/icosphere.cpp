#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "vscan_test/meshes.h"

namespace vscan::test {
namespace {

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
  for (const auto& v : unit) mesh.vertices.push_back((centre + radius * v).cast<float>());
  mesh.triangles = std::move(faces);
  return mesh;
}

}  // namespace vscan::test
