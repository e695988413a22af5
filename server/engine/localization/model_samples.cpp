#include "localization/model_samples.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "random/seeded_draws.h"

namespace vscan::localization {

ModelSamples SampleModel(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  std::vector<double> cumulative_area;
  cumulative_area.reserve(mesh.triangles.size());
  double total = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    total += 0.5 * (mesh.vertices[t[1]].cast<double>() - a).cross(mesh.vertices[t[2]].cast<double>() - a).norm();
    cumulative_area.push_back(total);
  }
  ModelSamples samples;
  if (!(total > 0)) return samples;
  samples.points.reserve(count);
  samples.normals.reserve(count);
  random::SplitMix64Stream draws(seed);
  for (size_t i = 0; i < count; ++i) {
    const double at = draws.Uniform() * total;
    const size_t k = std::min<size_t>(
        static_cast<size_t>(std::upper_bound(cumulative_area.begin(), cumulative_area.end(), at) -
                            cumulative_area.begin()),
        mesh.triangles.size() - 1);
    const auto& t = mesh.triangles[k];
    const Eigen::Vector3f a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    // Folding the unit square onto the triangle keeps the draw uniform over its area.
    auto u = static_cast<float>(draws.Uniform()), v = static_cast<float>(draws.Uniform());
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    samples.points.push_back(a + u * (b - a) + v * (c - a));
    samples.normals.push_back((b - a).cross(c - a).normalized());
  }
  return samples;
}

}  // namespace vscan::localization
