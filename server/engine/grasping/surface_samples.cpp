#include "grasping/surface_samples.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Geometry>

#include "random/seeded_draws.h"

namespace vscan::grasping {

SurfaceSamples SampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>(), b = mesh.vertices[tri[1]].cast<double>(),
                          c = mesh.vertices[tri[2]].cast<double>();
    total += 0.5 * (b - a).cross(c - a).norm();
    cumulative[t] = total;
  }
  SurfaceSamples out;
  out.area = total;
  out.points.reserve(count);
  out.normals.reserve(count);
  random::KeyedDraws draws(random::SplitMix64(seed));
  for (size_t i = 0; i < count; ++i) {
    const double pick = draws.Uniform() * total;
    const size_t t = std::min<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(),
                                      cumulative.size() - 1);
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>(), b = mesh.vertices[tri[1]].cast<double>(),
                          c = mesh.vertices[tri[2]].cast<double>();
    const double r1 = std::sqrt(draws.Uniform()), r2 = draws.Uniform();
    out.points.push_back((1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    out.normals.push_back(n.norm() > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::UnitZ());
  }
  return out;
}

SampleGrid::SampleGrid(const std::vector<Eigen::Vector3d>& points, double cell_size) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(0), hi = Eigen::Vector3d::Constant(0);
  if (!points.empty()) lo = hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  origin_ = lo;
  // Coarser cells for a tiny cell size on a large part keep every cell index within 20 bits.
  cell_size_ = std::max(cell_size, (hi - lo).maxCoeff() / 1e5 + 1e-12);
  max_cell_ = (1 << 20) - 1;
  std::vector<std::pair<int64_t, uint32_t>> keyed(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Array3i c = Cell(points[i]);
    keyed[i] = {Key(c.x(), c.y(), c.z()), static_cast<uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  order_.resize(keyed.size());
  for (size_t i = 0; i < keyed.size(); ++i) {
    order_[i] = keyed[i].second;
    auto [it, added] = cells_.try_emplace(keyed[i].first, static_cast<uint32_t>(i), static_cast<uint32_t>(i));
    it->second.second = static_cast<uint32_t>(i + 1);
  }
}

Eigen::Array3i SampleGrid::Cell(const Eigen::Vector3d& p) const {
  const Eigen::Array3d c = ((p - origin_) / cell_size_).array().floor().cwiseMax(-1).cwiseMin(max_cell_);
  return c.cast<int>();
}

int64_t SampleGrid::Key(int x, int y, int z) {
  // Cells run from -1 to 2^20 - 1: shifted by one they fit 21 bits each.
  return (int64_t(x + 1) << 42) | (int64_t(y + 1) << 21) | int64_t(z + 1);
}

}  // namespace vscan::grasping
