#include "evaluation/nearest_distances.h"

#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace vscan::evaluation {

std::vector<float> NearestDistances(const spatial::KdTree& tree, std::span<const Eigen::Vector3f> queries) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  std::vector<float> distances(queries.size(), kInf);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, queries.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    spatial::Neighbor nearest[1];
    for (size_t i = r.begin(); i != r.end(); ++i) {
      if (!queries[i].allFinite()) continue;
      if (tree.Knn(queries[i], kInf, nearest) == 1) distances[i] = std::sqrt(nearest[0].dist_sq);
    }
  });
  return distances;
}

}  // namespace vscan::evaluation
