#include "physics/part_geometry.h"

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/convex_decomposition.h"

namespace vscan::physics {
namespace {

struct VolumeAndCentre {
  double volume = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

// Signed tetrahedra from the origin (divergence theorem); exact for a closed mesh.
VolumeAndCentre EnclosedVolume(const TriangleMesh& mesh) {
  VolumeAndCentre out;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[t[2]].cast<double>();
    const double v = a.dot(b.cross(c)) / 6.0;
    out.volume += v;
    weighted += v * (a + b + c) / 4.0;
  }
  if (out.volume < 0) {  // inward-facing triangles
    out.volume = -out.volume;
    weighted = -weighted;
  }
  if (out.volume > 0) out.centre = weighted / out.volume;
  return out;
}

Eigen::Vector3d BoundsCentre(const TriangleMesh& mesh, double& box_volume) {
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  box_volume = static_cast<double>((hi - lo).prod());
  return (0.5f * (lo + hi)).cast<double>();
}

}  // namespace

std::vector<Eigen::Vector3d> ExactHull(const TriangleMesh& mesh, const Eigen::Vector3d& centre) {
  std::vector<double> coords;
  coords.reserve(mesh.vertices.size() * 3);
  for (const Eigen::Vector3f& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) coords.push_back(static_cast<double>(v[k]) - centre[k]);
  }
  btConvexHullComputer computer;
  computer.compute(coords.data(), 3 * sizeof(double), static_cast<int>(mesh.vertices.size()), 0, 0);
  std::vector<Eigen::Vector3d> out;
  if (computer.vertices.size() >= 4) {
    for (int i = 0; i < computer.vertices.size(); ++i) {
      const btVector3& p = computer.vertices[i];
      out.emplace_back(p.x(), p.y(), p.z());
    }
  } else {  // flat: keep every point
    for (size_t i = 0; i + 2 < coords.size(); i += 3) out.emplace_back(coords[i], coords[i + 1], coords[i + 2]);
  }
  return out;
}

std::vector<Eigen::Vector3d> FarthestPoints(const std::vector<Eigen::Vector3d>& points, int count) {
  if (points.size() <= static_cast<size_t>(count)) return points;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  std::vector<double> nearest(points.size(), std::numeric_limits<double>::infinity());
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(static_cast<size_t>(count));
  size_t next = 0;
  double best = -1;
  for (size_t i = 0; i < points.size(); ++i) {
    const double d = (points[i] - mean).squaredNorm();
    if (d > best) best = d, next = i;
  }
  while (kept.size() < static_cast<size_t>(count)) {
    kept.push_back(points[next]);
    best = -1;
    for (size_t i = 0; i < points.size(); ++i) {
      nearest[i] = std::min(nearest[i], (points[i] - kept.back()).squaredNorm());
      if (nearest[i] > best) best = nearest[i], next = i;
    }
  }
  return kept;
}

PartGeometry MakePartGeometry(const PartType& part, int max_hull_vertices) {
  PartGeometry out;
  const VolumeAndCentre enclosed = EnclosedVolume(part.mesh);
  double box_volume = 0.0;
  const Eigen::Vector3d box_centre = BoundsCentre(part.mesh, box_volume);
  // An open or flat mesh encloses nothing useful: fall back to its bounding box.
  const bool closed = enclosed.volume > 1e-3 * box_volume && enclosed.volume > 0;
  out.centre = closed ? enclosed.centre : box_centre;
  const double volume = closed ? enclosed.volume : box_volume;
  out.mass_kg = part.mass_kg.value_or(part.density_kg_per_m3 * volume);
  out.hull = FarthestPoints(ExactHull(part.mesh, out.centre), max_hull_vertices);
  for (const auto& p : out.hull) out.radius = std::max(out.radius, p.norm());
  if (part.collision == PartCollision::kConvexDecomposition) {
    out.pieces = ConvexPieces(part.mesh, out.centre, max_hull_vertices);
  }
  return out;
}

std::vector<PartGeometry> MakePartGeometries(const std::vector<PartType>& parts, int max_hull_vertices) {
  std::vector<PartGeometry> out;
  out.reserve(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    PartType hull_only = parts[i];
    size_t same = 0;
    const auto same_mesh = [&](size_t j) {
      return parts[j].collision == PartCollision::kConvexDecomposition && parts[j].mesh.vertices == parts[i].mesh.vertices &&
             parts[j].mesh.triangles == parts[i].mesh.triangles;
    };
    while (same < i && !same_mesh(same)) ++same;
    const bool reuse = parts[i].collision == PartCollision::kConvexDecomposition && same < i;
    if (reuse) hull_only.collision = PartCollision::kConvexHull;
    out.push_back(MakePartGeometry(reuse ? hull_only : parts[i], max_hull_vertices));
    if (reuse) out.back().pieces = out[same].pieces;  // same mesh, same centre: the same pieces
  }
  return out;
}

}  // namespace vscan::physics
