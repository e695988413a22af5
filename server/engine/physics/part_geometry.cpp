#include "physics/part_geometry.h"

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "physics/convex_decomposition.h"
#include "physics/mesh_depth.h"

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

double PlaneDistance(const Eigen::Vector3d& p, const std::vector<HullFace>& facets) {
  double out = -std::numeric_limits<double>::infinity();
  for (const HullFace& f : facets) out = std::max(out, f.normal.dot(p) - f.offset);
  return out;
}

// Euclidean distance from a point outside the hull to it: the nearest point of a face it sees.
double OutsideDistance(const Eigen::Vector3d& p, const std::vector<HullFace>& facets) {
  double best = std::numeric_limits<double>::infinity();
  for (const HullFace& f : facets) {
    if (f.normal.dot(p) - f.offset <= 0) continue;
    for (size_t i = 1; i + 1 < f.corners.size(); ++i) {
      best = std::min(best, (ClosestPointOnTriangle(p, f.corners[0], f.corners[i], f.corners[i + 1]) - p).norm());
    }
  }
  return std::isfinite(best) ? best : 0.0;
}

std::vector<size_t> FarthestIndices(const std::vector<Eigen::Vector3d>& points, size_t count) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  std::vector<double> nearest(points.size(), std::numeric_limits<double>::infinity());
  std::vector<size_t> kept;
  size_t next = 0;
  double best = -1;
  for (size_t i = 0; i < points.size(); ++i) {
    const double d = (points[i] - mean).squaredNorm();
    if (d > best) best = d, next = i;
  }
  while (kept.size() < std::min(count, points.size())) {
    kept.push_back(next);
    best = -1;
    for (size_t i = 0; i < points.size(); ++i) {
      nearest[i] = std::min(nearest[i], (points[i] - points[kept.back()]).squaredNorm());
      if (nearest[i] > best) best = nearest[i], next = i;
    }
  }
  return kept;
}

}  // namespace

std::vector<HullFace> HullFaces(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> coords;
  coords.reserve(3 * points.size());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) {
    coords.insert(coords.end(), {p.x(), p.y(), p.z()});
    mean += p;
  }
  mean /= static_cast<double>(points.size());
  btConvexHullComputer computer;
  computer.compute(coords.data(), 3 * sizeof(double), static_cast<int>(points.size()), 0, 0);
  const auto vertex = [&](int i) {
    const btVector3& v = computer.vertices[i];
    return Eigen::Vector3d(v.x(), v.y(), v.z());
  };
  std::vector<HullFace> facets;
  for (int f = 0; f < computer.faces.size(); ++f) {
    HullFace facet;
    const btConvexHullComputer::Edge* first = &computer.edges[computer.faces[f]];
    const btConvexHullComputer::Edge* edge = first;
    do {
      facet.corners.push_back(vertex(edge->getSourceVertex()));
      edge = edge->getNextEdgeOfFace();
    } while (edge != first && facet.corners.size() < 4096);
    const size_t n = facet.corners.size();
    if (n < 3) continue;
    // Newell's normal: robust for polygons with nearly collinear corners.
    for (size_t i = 0; i < n; ++i) facet.normal += facet.corners[i].cross(facet.corners[(i + 1) % n]);
    if (!(facet.normal.norm() > 0)) continue;
    facet.normal.normalize();
    facet.offset = facet.normal.dot(facet.corners[0]);
    if (facet.normal.dot(mean) - facet.offset > 1e-12) {  // the winding faced inward
      facet.normal = -facet.normal;
      facet.offset = -facet.offset;
    }
    facets.push_back(std::move(facet));
  }
  return facets;
}

double HullVolume(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 4) return 0.0;
  double volume = 0.0;
  for (const HullFace& f : HullFaces(points)) {
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < f.corners.size(); ++i) area += f.corners[i].cross(f.corners[(i + 1) % f.corners.size()]);
    volume += f.offset * 0.5 * area.norm() / 3.0;
  }
  return std::max(0.0, volume);
}

double MeshVolume(const TriangleMesh& mesh) { return EnclosedVolume(mesh).volume; }

std::vector<Eigen::Vector3d> HullVertices(const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> coords;
  for (const auto& p : points) coords.insert(coords.end(), {p.x(), p.y(), p.z()});
  btConvexHullComputer computer;
  computer.compute(coords.data(), 3 * sizeof(double), static_cast<int>(points.size()), 0, 0);
  if (computer.vertices.size() < 4) return points;
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < computer.vertices.size(); ++i) {
    out.emplace_back(computer.vertices[i].x(), computer.vertices[i].y(), computer.vertices[i].z());
  }
  return out;
}

double DistanceOutsideHull(const Eigen::Vector3d& point, const std::vector<Eigen::Vector3d>& hull) {
  const std::vector<HullFace> facets = HullFaces(hull);
  return PlaneDistance(point, facets) <= 0 ? 0.0 : OutsideDistance(point, facets);
}

namespace {

// Whether any point of triangle (a, b, c) lies more than `tolerance` under the hull's surface. The
// depth, min over the faces of (offset - normal . p), is concave: its maximum over the triangle
// is at most the least over the faces of that face's largest value at a corner; where that bound
// is over the tolerance and no corner is, the triangle is cut in four.
bool DeeperThan(const std::vector<HullFace>& facets, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const Eigen::Vector3d& c, double tolerance, int level) {
  double bound = std::numeric_limits<double>::infinity();
  for (const HullFace& f : facets) {
    bound = std::min(bound, f.offset - std::min({f.normal.dot(a), f.normal.dot(b), f.normal.dot(c)}));
  }
  if (bound <= tolerance) return false;
  for (const Eigen::Vector3d* p : {&a, &b, &c}) {
    if (-PlaneDistance(*p, facets) > tolerance) return true;
  }
  if (level == 0) return true;  // undecided this fine: not within
  const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  return DeeperThan(facets, a, ab, ca, tolerance, level - 1) || DeeperThan(facets, ab, b, bc, tolerance, level - 1) ||
         DeeperThan(facets, ca, bc, c, tolerance, level - 1) || DeeperThan(facets, ab, bc, ca, tolerance, level - 1);
}

}  // namespace

bool ConvexWithin(const TriangleMesh& mesh, const Eigen::Vector3d& centre, const std::vector<Eigen::Vector3d>& hull,
                  double tolerance) {
  const std::vector<HullFace> facets = HullFaces(hull);
  if (facets.size() < 4) return false;
  for (const auto& t : mesh.triangles) {
    const auto at = [&](int k) { return Eigen::Vector3d(mesh.vertices[t[k]].cast<double>() - centre); };
    if (DeeperThan(facets, at(0), at(1), at(2), tolerance, 8)) return false;
  }
  // What lies between the hull and a mesh within `tolerance` of it fits in a shell that thick
  // under the hull's faces: a hollow behind a thin wall (a tube's bore) does not.
  double area = 0.0;
  for (const HullFace& f : facets) {
    Eigen::Vector3d twice = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < f.corners.size(); ++i) twice += f.corners[i].cross(f.corners[(i + 1) % f.corners.size()]);
    area += 0.5 * twice.norm();
  }
  return HullVolume(hull) - MeshVolume(mesh) <= tolerance * area;
}

std::vector<Eigen::Vector3d> SimplifiedHull(const std::vector<Eigen::Vector3d>& points, double tolerance) {
  if (points.size() <= 4 || !(tolerance > 0)) return points;
  std::vector<bool> used(points.size(), false);
  std::vector<Eigen::Vector3d> kept;
  for (size_t i : FarthestIndices(points, 4)) used[i] = true, kept.push_back(points[i]);
  while (kept.size() < points.size()) {
    const std::vector<HullFace> facets = HullFaces(kept);
    if (facets.size() < 2) return points;
    // The point farthest outside by its planes (a lower bound of its distance) while one lies
    // farther than the tolerance; then the Euclidean distances of those nearer.
    size_t worst = points.size();
    double worst_distance = tolerance;
    std::vector<size_t> near;
    for (size_t i = 0; i < points.size(); ++i) {
      if (used[i]) continue;
      const double d = PlaneDistance(points[i], facets);
      if (d > worst_distance) {
        worst = i, worst_distance = d;
      } else if (d > 0) {
        near.push_back(i);
      }
    }
    if (worst == points.size()) {
      for (size_t i : near) {
        const double d = OutsideDistance(points[i], facets);
        if (d > worst_distance) worst = i, worst_distance = d;
      }
    }
    if (worst == points.size()) break;
    used[worst] = true;
    kept.push_back(points[worst]);
  }
  return kept;
}

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
  std::vector<Eigen::Vector3d> kept;
  for (size_t i : FarthestIndices(points, static_cast<size_t>(count))) kept.push_back(points[i]);
  return kept;
}

PartGeometry MakePartGeometry(const PartType& part, double hull_tolerance_m) {
  PartGeometry out;
  const VolumeAndCentre enclosed = EnclosedVolume(part.mesh);
  double box_volume = 0.0;
  const Eigen::Vector3d box_centre = BoundsCentre(part.mesh, box_volume);
  // An open or flat mesh encloses nothing useful: fall back to its bounding box.
  const bool closed = enclosed.volume > 1e-3 * box_volume && enclosed.volume > 0;
  out.centre = closed ? enclosed.centre : box_centre;
  const double volume = closed ? enclosed.volume : box_volume;
  out.mass_kg = part.mass_kg.value_or(part.density_kg_per_m3 * volume);
  out.hull = SimplifiedHull(ExactHull(part.mesh, out.centre), hull_tolerance_m);
  for (const auto& p : out.hull) out.radius = std::max(out.radius, p.norm());
  if (part.collision == PartCollision::kConvexDecomposition) {
    out.pieces = ConvexPieces(part.mesh, out.centre, hull_tolerance_m);
  }
  return out;
}

std::vector<PartGeometry> MakePartGeometries(const std::vector<PartType>& parts, double hull_tolerance_m) {
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
    out.push_back(MakePartGeometry(reuse ? hull_only : parts[i], hull_tolerance_m));
    if (reuse) out.back().pieces = out[same].pieces;  // same mesh, same centre: the same pieces
  }
  return out;
}

}  // namespace vscan::physics
