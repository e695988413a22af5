#include "reconstruction/distance_trim.h"

#include <vector>

#include <tbb/parallel_for.h>

#include "spatial/kd_tree.h"
#include "reconstruction/mesh_cleanup.h"

namespace vscan::reconstruction {

size_t TrimFarFromPoints(TriangleMesh& mesh, std::span<const Eigen::Vector3f> points, float max_distance) {
  const spatial::KdTree tree(points);
  std::vector<char> keep(mesh.vertices.size(), 0);
  const float max_sq = max_distance * max_distance;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertices.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    spatial::Neighbor nearest[1];
    for (size_t v = r.begin(); v != r.end(); ++v) keep[v] = tree.Knn(mesh.vertices[v], max_sq, nearest) == 1;
  });
  const size_t before = mesh.triangles.size();
  KeepTrianglesOnVertices(mesh, std::vector<bool>(keep.begin(), keep.end()));
  return before - mesh.triangles.size();
}

}  // namespace vscan::reconstruction
