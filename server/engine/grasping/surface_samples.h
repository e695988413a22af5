#pragma once
// Area-weighted seeded samples of a mesh surface with their face normals, and a hashed grid over
// them for "which samples lie near this point" queries.

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"

namespace vscan::grasping {

struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  // unit face normals (outward for a mesh wound counter-clockwise)
  double area = 0;                       // total surface area, m^2
};

// `count` points drawn area-weighted with the seed (zero-area triangles are never drawn). The mesh
// must be validated (indices in range, finite vertices, positive area).
SurfaceSamples SampleSurface(const TriangleMesh& mesh, size_t count, uint64_t seed);

class SampleGrid {
 public:
  SampleGrid(const std::vector<Eigen::Vector3d>& points, double cell_size);
  // Calls visit(index) for every point within the axis-aligned box [lo, hi] (and some just outside).
  template <typename Visit>
  void VisitBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Visit visit) const {
    const Eigen::Array3i a = Cell(lo), b = Cell(hi);
    for (int x = a.x(); x <= b.x(); ++x)
      for (int y = a.y(); y <= b.y(); ++y)
        for (int z = a.z(); z <= b.z(); ++z) {
          const auto it = cells_.find(Key(x, y, z));
          if (it == cells_.end()) continue;
          for (uint32_t i = it->second.first; i < it->second.second; ++i) visit(order_[i]);
        }
  }

 private:
  Eigen::Array3i Cell(const Eigen::Vector3d& p) const;
  static int64_t Key(int x, int y, int z);

  Eigen::Vector3d origin_;
  double cell_size_;
  int max_cell_;
  std::vector<uint32_t> order_;
  std::unordered_map<int64_t, std::pair<uint32_t, uint32_t>> cells_;
};

}  // namespace vscan::grasping
