#include "grasping/mesh_rays.h"

#include <cmath>

#include <Eigen/Geometry>

namespace vscan::grasping {

MeshRays::MeshRays(const TriangleMesh& mesh) {
  triangles_.reserve(mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>();
    const Eigen::Vector3d e1 = mesh.vertices[tri[1]].cast<double>() - a, e2 = mesh.vertices[tri[2]].cast<double>() - a;
    const Eigen::Vector3d n = e1.cross(e2);
    if (!(n.norm() > 0)) continue;  // degenerate: nothing to hit
    triangles_.push_back({a, e1, e2, n.normalized()});
  }
}

std::optional<RayHit> MeshRays::FirstHit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                         double min_distance, double max_distance) const {
  std::optional<RayHit> best;
  double best_t = max_distance;
  for (const auto& tri : triangles_) {
    const Eigen::Vector3d p = direction.cross(tri.edge2);
    const double det = tri.edge1.dot(p);
    if (std::abs(det) < 1e-18) continue;
    const double inv = 1.0 / det;
    const Eigen::Vector3d s = origin - tri.a;
    const double u = s.dot(p) * inv;
    if (u < 0 || u > 1) continue;
    const Eigen::Vector3d q = s.cross(tri.edge1);
    const double v = direction.dot(q) * inv;
    if (v < 0 || u + v > 1) continue;
    const double t = tri.edge2.dot(q) * inv;
    if (t > min_distance && t <= best_t) {
      best_t = t;
      best = RayHit{t, tri.normal};
    }
  }
  return best;
}

}  // namespace vscan::grasping
