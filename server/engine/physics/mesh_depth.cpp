#include "physics/mesh_depth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/closest_point.h"
#include "physics/part_geometry.h"

namespace vscan::physics {
namespace {

constexpr uint32_t kLeafTriangles = 4;
// Past this many hull faces the planes cost more a query than the tree (a dense smooth part).
constexpr size_t kMaxHullPlanes = 512;

// Directions for the inside test: none along an axis or a diagonal, where a mesh's edges tend to be.
const Eigen::Vector3d kRayDirections[] = {
    Eigen::Vector3d(0.5377, 0.2319, 0.8106).normalized(),
    Eigen::Vector3d(-0.3141, 0.8923, -0.3245).normalized(),
    Eigen::Vector3d(0.7071, -0.5592, -0.4329).normalized(),
};

bool RayHitsBox(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& inverse) {
  double near = 0.0, far = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    double t0 = (box.min()[k] - origin[k]) * inverse[k];
    double t1 = (box.max()[k] - origin[k]) * inverse[k];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  return near <= far;
}

}  // namespace

Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c) {
  return geometry::ClosestPointOnTriangle<double>(p, a, b, c);
}

MeshDepth::MeshDepth(const TriangleMesh& mesh) : triangles_(mesh.triangles) {
  vertices_.reserve(mesh.vertices.size());
  for (const Eigen::Vector3f& v : mesh.vertices) vertices_.push_back(v.cast<double>());
  for (const auto& t : triangles_) {
    for (int k = 0; k < 3; ++k) edges_.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  std::vector<Eigen::Vector3d> centroids;
  centroids.reserve(triangles_.size());
  for (const auto& t : triangles_) centroids.push_back((vertices_[t[0]] + vertices_[t[1]] + vertices_[t[2]]) / 3.0);
  order_.resize(triangles_.size());
  for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
  nodes_.reserve(2 * triangles_.size() / kLeafTriangles + 2);
  Build(0, static_cast<uint32_t>(order_.size()), centroids);
  if (vertices_.size() >= 4) {
    const std::vector<HullFace> faces = HullFaces(vertices_);
    if (faces.size() >= 4 && faces.size() <= kMaxHullPlanes) {
      for (const HullFace& face : faces) hull_planes_.emplace_back(face.normal.x(), face.normal.y(), face.normal.z(), face.offset);
      // A vertex on a hull plane is not enough (an L's notch corner lies on its top face): no point
      // of the triangles may lie under the hull's surface, and the hull encloses no more.
      convex_ = ConvexWithin(mesh, Eigen::Vector3d::Zero(), ExactHull(mesh, Eigen::Vector3d::Zero()),
                             1e-6 * bounds().sizes().maxCoeff());
      // The hull's corners come back from Bullet's hull in single precision: its planes missed a
      // 96-sided prism's faces by up to a micrometre, and a depth read from them understated the
      // distance to the surface. A convex mesh's own triangles lie on its hull: their planes, once each.
      // Kept to a few times the hull's faces (a finely cut tilted face gives each triangle its
      // own rounding), else the search for known planes would grow with the triangles squared.
      std::vector<Eigen::Vector4d> own_planes;
      for (uint32_t t = 0; convex_ && t < triangles_.size() && own_planes.size() <= 4 * kMaxHullPlanes; ++t) {
        const Eigen::Vector3d n = Normal(t);
        if (!n.allFinite()) continue;
        const double offset = n.dot(vertices_[triangles_[t][0]]);
        const bool known = std::any_of(own_planes.begin(), own_planes.end(), [&](const Eigen::Vector4d& plane) {
          return plane.head<3>().dot(n) > 1 - 1e-12 && std::abs(plane.w() - offset) < 1e-12;
        });
        if (!known) own_planes.emplace_back(n.x(), n.y(), n.z(), offset);
      }
      if (convex_ && own_planes.size() <= 4 * kMaxHullPlanes) hull_planes_ = std::move(own_planes);
    }
  }
}

double MeshDepth::BeyondHull(const Eigen::Vector3d& p) const {
  double beyond = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector4d& plane : hull_planes_) beyond = std::max(beyond, plane.head<3>().dot(p) - plane.w());
  return beyond;
}

uint32_t MeshDepth::Build(uint32_t begin, uint32_t end, const std::vector<Eigen::Vector3d>& centroids) {
  const auto node = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box, centre_box;
  for (uint32_t i = begin; i < end; ++i) {
    for (uint32_t v : triangles_[order_[i]]) box.extend(vertices_[v]);
    centre_box.extend(centroids[order_[i]]);
  }
  nodes_[node].box = box;
  if (end - begin <= kLeafTriangles) {
    nodes_[node].first = begin;
    nodes_[node].count = end - begin;
    return node;
  }
  int axis = 0;
  centre_box.sizes().maxCoeff(&axis);
  const uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                   [&](uint32_t x, uint32_t y) { return centroids[x][axis] < centroids[y][axis]; });
  const uint32_t left = Build(begin, middle, centroids);
  const uint32_t right = Build(middle, end, centroids);
  nodes_[node].first = left;
  nodes_[node].right = right;
  return node;
}

Eigen::Vector3d MeshDepth::Normal(uint32_t triangle) const {
  const auto& t = triangles_[triangle];
  return (vertices_[t[1]] - vertices_[t[0]]).cross(vertices_[t[2]] - vertices_[t[0]]).normalized();
}

double MeshDepth::Distance(const Eigen::Vector3d& p, uint32_t* triangle) const {
  double best = std::numeric_limits<double>::infinity();
  uint32_t nearest = 0;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.box.squaredExteriorDistance(p) >= best) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const auto& t = triangles_[order_[i]];
        const double d = (ClosestPointOnTriangle(p, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]) - p).squaredNorm();
        if (d < best) best = d, nearest = order_[i];
      }
      continue;
    }
    const double left = nodes_[node.first].box.squaredExteriorDistance(p);
    const double right = nodes_[node.right].box.squaredExteriorDistance(p);
    // The nearer child on top of the stack.
    if (left < right) {
      stack[top++] = node.right;
      stack[top++] = node.first;
    } else {
      stack[top++] = node.first;
      stack[top++] = node.right;
    }
  }
  if (triangle != nullptr) *triangle = nearest;
  return std::sqrt(best);
}

int MeshDepth::Crossings(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, bool& grazing) const {
  constexpr double kEdge = 1e-9;
  const Eigen::Vector3d inverse = direction.cwiseInverse();
  int crossings = 0;
  uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!RayHitsBox(node.box, origin, inverse)) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = node.right;
      continue;
    }
    for (uint32_t i = node.first; i < node.first + node.count; ++i) {
      const auto& t = triangles_[order_[i]];
      const Eigen::Vector3d& a = vertices_[t[0]];
      const Eigen::Vector3d e1 = vertices_[t[1]] - a, e2 = vertices_[t[2]] - a;
      const Eigen::Vector3d pvec = direction.cross(e2);
      const double det = e1.dot(pvec);
      if (std::abs(det) < 1e-30) continue;  // parallel (or degenerate): no crossing
      const Eigen::Vector3d tvec = origin - a;
      const double u = tvec.dot(pvec) / det;
      if (u < -kEdge || u > 1 + kEdge) continue;
      const Eigen::Vector3d qvec = tvec.cross(e1);
      const double v = direction.dot(qvec) / det;
      if (v < -kEdge || u + v > 1 + kEdge) continue;
      const double t_hit = e2.dot(qvec) / det;
      if (t_hit <= 0) continue;
      if (u < kEdge || v < kEdge || u + v > 1 - kEdge) grazing = true;
      ++crossings;
    }
  }
  return crossings;
}

bool MeshDepth::Inside(const Eigen::Vector3d& p) const {
  if (triangles_.empty() || !bounds().contains(p) || BeyondHull(p) > 0) return false;
  if (convex_) return true;
  int votes = 0;
  for (const Eigen::Vector3d& direction : kRayDirections) {
    bool grazing = false;
    const bool inside = Crossings(p, direction, grazing) % 2 == 1;
    if (!grazing) return inside;
    votes += inside ? 1 : 0;
  }
  return votes >= 2;
}

double MeshDepth::SignedDepth(const Eigen::Vector3d& p) const {
  if (triangles_.empty()) return -std::numeric_limits<double>::infinity();
  if (!bounds().contains(p)) return -std::sqrt(bounds().squaredExteriorDistance(p));
  if (const double beyond = BeyondHull(p); beyond > 0 || convex_) return -beyond;
  const double distance = Distance(p);
  return Inside(p) ? distance : -distance;
}

}  // namespace vscan::physics
