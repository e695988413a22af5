#pragma once
// Signed depth of points against a closed triangle mesh: how far inside it a point lies (the
// distance to its surface), negative outside. A bounding-volume hierarchy over the triangles;
// inside by the parity of a ray's crossings.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vscan/common/mesh.h"

namespace vscan::physics {

// The closest point of triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d ClosestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

class MeshDepth {
 public:
  explicit MeshDepth(const TriangleMesh& mesh);

  // Distance to the surface, positive inside and negative outside. Outside the mesh's convex hull
  // it is minus the distance to the nearest hull plane it lies beyond, or to the bounding box (no
  // farther than the surface: a bound, cheaply). Inside a convex mesh it is the nearest face's
  // plane distance, without the tree.
  double SignedDepth(const Eigen::Vector3d& p) const;
  // The nearest triangle's index and the distance to it.
  double Distance(const Eigen::Vector3d& p, uint32_t* triangle = nullptr) const;
  bool Inside(const Eigen::Vector3d& p) const;

  const Eigen::AlignedBox3d& bounds() const { return nodes_.front().box; }
  const std::vector<Eigen::Vector3d>& vertices() const { return vertices_; }
  const std::vector<std::array<uint32_t, 3>>& triangles() const { return triangles_; }
  // Every edge once, as vertex indices.
  const std::vector<std::array<uint32_t, 2>>& edges() const { return edges_; }
  // The triangle's unit normal by its winding (a, b, c counter-clockwise seen from the front).
  Eigen::Vector3d Normal(uint32_t triangle) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    uint32_t first = 0;  // leaf: the first of its triangles in order_; inner: the left child
    uint32_t right = 0;  // inner: the right child
    uint32_t count = 0;  // triangles in a leaf, 0 for an inner node
  };
  uint32_t Build(uint32_t begin, uint32_t end, const std::vector<Eigen::Vector3d>& centroids);
  int Crossings(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, bool& grazing) const;
  // How far p lies beyond the hull's planes (<= 0 inside the hull; -infinity without a hull).
  double BeyondHull(const Eigen::Vector3d& p) const;

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<std::array<uint32_t, 3>> triangles_;
  std::vector<std::array<uint32_t, 2>> edges_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
  // The convex hull's faces as (normal, offset), inside where normal . p <= offset: a point outside
  // them is outside the mesh, decided without the tree. Empty for a hull of more than 512 faces.
  std::vector<Eigen::Vector4d> hull_planes_;
  // The mesh is its hull (ConvexWithin a micrometre a metre of its size): depths inside it are plane
  // distances.
  bool convex_ = false;
};

}  // namespace vscan::physics
