#pragma once
// Exact contact tests between convex pieces (the gripper's sweep) and triangle meshes, by
// separating axes: the piece's face normals, the triangle's normal and the cross products of
// their edges. Touching counts as contact.

#include <vector>

#include <Eigen/Core>

#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"

namespace vscan::grasping {

class ConvexPiece {
 public:
  // From a closed convex mesh; parallel face normals and edge directions are kept once.
  explicit ConvexPiece(const TriangleMesh& mesh);

  // The piece moved by frame_from_piece.
  ConvexPiece Placed(const Pose3& frame_from_piece) const;

  bool MeetsTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const;
  // Whether any triangle of mesh (in this piece's frame) meets the piece.
  bool MeetsMesh(const TriangleMesh& mesh) const;

  const Eigen::Vector3d& lo() const { return lo_; }
  const Eigen::Vector3d& hi() const { return hi_; }

 private:
  ConvexPiece() = default;
  void UpdateBounds();

  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3d> face_normals_;
  std::vector<Eigen::Vector3d> edge_directions_;
  Eigen::Vector3d lo_, hi_;
};

}  // namespace vscan::grasping
