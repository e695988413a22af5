#include "reconstruction/mesh_cleanup.h"

#include <cstdint>
#include <numeric>

namespace vscan::reconstruction {
namespace {

// Union-find over vertex ids with path halving.
class DisjointSets {
 public:
  explicit DisjointSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), uint32_t{0}); }
  uint32_t Find(uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void Join(uint32_t a, uint32_t b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[a < b ? b : a] = a < b ? a : b;
  }

 private:
  std::vector<uint32_t> parent_;
};

}  // namespace

void DropUnusedVertices(TriangleMesh& mesh) {
  constexpr uint32_t kUnused = UINT32_MAX;
  std::vector<uint32_t> remap(mesh.vertices.size(), kUnused);
  for (const auto& tri : mesh.triangles) {
    for (uint32_t v : tri) remap[v] = 0;
  }
  uint32_t next = 0;
  for (size_t v = 0; v < remap.size(); ++v) {
    if (remap[v] == kUnused) continue;
    remap[v] = next;
    mesh.vertices[next++] = mesh.vertices[v];
  }
  mesh.vertices.resize(next);
  for (auto& tri : mesh.triangles) {
    for (uint32_t& v : tri) v = remap[v];
  }
}

void KeepTrianglesOnVertices(TriangleMesh& mesh, const std::vector<bool>& keep_vertex) {
  std::erase_if(mesh.triangles, [&](const std::array<uint32_t, 3>& tri) {
    return !keep_vertex[tri[0]] || !keep_vertex[tri[1]] || !keep_vertex[tri[2]];
  });
  DropUnusedVertices(mesh);
}

size_t RemoveSmallComponents(TriangleMesh& mesh, size_t min_triangles) {
  if (min_triangles <= 1 || mesh.triangles.empty()) return 0;
  DisjointSets sets(mesh.vertices.size());
  for (const auto& tri : mesh.triangles) {
    sets.Join(tri[0], tri[1]);
    sets.Join(tri[0], tri[2]);
  }
  std::vector<uint32_t> size(mesh.vertices.size(), 0);
  for (const auto& tri : mesh.triangles) ++size[sets.Find(tri[0])];
  const size_t before = mesh.triangles.size();
  std::erase_if(mesh.triangles,
                [&](const std::array<uint32_t, 3>& tri) { return size[sets.Find(tri[0])] < min_triangles; });
  DropUnusedVertices(mesh);
  return before - mesh.triangles.size();
}

}  // namespace vscan::reconstruction
