#include "evaluation/surface_sampling.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "random/seeded_draws.h"

namespace vscan::evaluation {
namespace {

double TriangleArea(const TriangleMesh& mesh, size_t t) {
  const auto& tri = mesh.triangles[t];
  const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>();
  const Eigen::Vector3d b = mesh.vertices[tri[1]].cast<double>();
  const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>();
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

double SurfaceArea(const TriangleMesh& mesh) {
  double area = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) area += TriangleArea(mesh, t);
  return area;
}

std::vector<Eigen::Vector3f> SampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed,
                                           std::vector<Eigen::Vector3f>* face_normals) {
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) cumulative[t] = total += TriangleArea(mesh, t);
  if (total <= 0 || count == 0) return {};
  std::vector<Eigen::Vector3f> samples(count);
  if (face_normals) face_normals->assign(count, Eigen::Vector3f::Zero());
  const uint64_t key = random::SplitMix64(seed);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      random::KeyedDraws draws(key + 3 * i);
      const double pick = draws.Uniform() * total;
      const size_t t = std::min<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
                                        cumulative.size() - 1);
      // Square-root warp: (1 - s, s * (1 - w), s * w) is uniform over the triangle.
      const double s = std::sqrt(draws.Uniform());
      const double w = draws.Uniform();
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d p = (1 - s) * mesh.vertices[tri[0]].cast<double>() +
                                s * (1 - w) * mesh.vertices[tri[1]].cast<double>() +
                                s * w * mesh.vertices[tri[2]].cast<double>();
      samples[i] = p.cast<float>();
      if (face_normals) {
        const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>();
        const Eigen::Vector3d n = (mesh.vertices[tri[1]].cast<double>() - a).cross(mesh.vertices[tri[2]].cast<double>() - a);
        (*face_normals)[i] = n.normalized().cast<float>();
      }
    }
  });
  return samples;
}

}  // namespace vscan::evaluation
