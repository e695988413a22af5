#include "registration/normal_orientation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <queue>
#include <tuple>
#include <utility>
#include <vector>

#include "spatial/kd_tree.h"

namespace vscan::registration {
namespace {

// The undirected neighbour graph in compressed rows: the neighbours of i are
// targets[offsets[i] .. offsets[i + 1]).
struct Graph {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> targets;
};

Graph NeighbourGraph(std::span<const Eigen::Vector3f> points, int k, float max_distance) {
  const spatial::KdTree tree(points);
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(points.size() * static_cast<size_t>(k));
  std::vector<spatial::Neighbor> found(static_cast<size_t>(k) + 1);
  for (uint32_t i = 0; i < points.size(); ++i) {
    const size_t count = tree.Knn(points[i], max_distance * max_distance, found);
    for (size_t n = 0; n < count; ++n) {
      const uint32_t j = tree.original_index(found[n].slot);
      if (j != i) edges.emplace_back(std::min(i, j), std::max(i, j));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  Graph graph;
  graph.offsets.assign(points.size() + 1, 0);
  for (const auto& [a, b] : edges) {
    ++graph.offsets[a + 1];
    ++graph.offsets[b + 1];
  }
  for (size_t i = 0; i < points.size(); ++i) graph.offsets[i + 1] += graph.offsets[i];
  graph.targets.resize(graph.offsets.back());
  std::vector<uint32_t> fill(graph.offsets.begin(), graph.offsets.end() - 1);
  for (const auto& [a, b] : edges) {
    graph.targets[fill[a]++] = b;
    graph.targets[fill[b]++] = a;
  }
  return graph;
}

}  // namespace

void OrientNormalsConsistently(std::span<const Eigen::Vector3f> points, std::span<Eigen::Vector3f> normals, int k,
                               float max_distance) {
  const Graph graph = NeighbourGraph(points, k, max_distance);
  std::vector<bool> reached(points.size(), false);
  // (1 - |cos| between the normals, point to reach, point it is reached from): Prim's frontier,
  // smallest first; the indices break ties so the tree does not depend on the heap.
  using Edge = std::tuple<float, uint32_t, uint32_t>;
  std::priority_queue<Edge, std::vector<Edge>, std::greater<>> frontier;
  std::vector<uint32_t> part;
  for (uint32_t root = 0; root < points.size(); ++root) {
    if (reached[root]) continue;
    part.clear();
    frontier.emplace(0.0f, root, root);
    while (!frontier.empty()) {
      const auto [cost, to, from] = frontier.top();
      frontier.pop();
      if (reached[to]) continue;
      reached[to] = true;
      part.push_back(to);
      if (normals[to].dot(normals[from]) < 0.0f) normals[to] = -normals[to];
      for (uint32_t e = graph.offsets[to]; e < graph.offsets[to + 1]; ++e) {
        const uint32_t next = graph.targets[e];
        if (!reached[next]) frontier.emplace(1.0f - std::abs(normals[to].dot(normals[next])), next, to);
      }
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (uint32_t i : part) centroid += points[i].cast<double>();
    centroid /= static_cast<double>(part.size());
    double outward = 0.0;
    for (uint32_t i : part) outward += (points[i].cast<double>() - centroid).dot(normals[i].cast<double>());
    if (outward < 0.0) {
      for (uint32_t i : part) normals[i] = -normals[i];
    }
  }
}

}  // namespace vscan::registration
