#include "grasping/sweep_contact.h"

#include <algorithm>
#include <array>
#include <limits>

namespace vscan::grasping {
namespace {

constexpr double kParallelSin2 = 1e-12;  // squared sine below which two directions are one

void AddDirection(std::vector<Eigen::Vector3d>& directions, const Eigen::Vector3d& d, bool signed_direction) {
  const double norm = d.norm();
  if (norm < 1e-15) return;
  const Eigen::Vector3d u = d / norm;
  for (const Eigen::Vector3d& e : directions) {
    if (u.cross(e).squaredNorm() < kParallelSin2 && (!signed_direction || u.dot(e) > 0)) return;
  }
  directions.push_back(u);
}

}  // namespace

ConvexPiece::ConvexPiece(const TriangleMesh& mesh) {
  for (const Eigen::Vector3f& v : mesh.vertices) vertices_.push_back(v.cast<double>());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = vertices_[t[0]], b = vertices_[t[1]], c = vertices_[t[2]];
    AddDirection(face_normals_, (b - a).cross(c - a), true);
    AddDirection(edge_directions_, b - a, false);
    AddDirection(edge_directions_, c - b, false);
    AddDirection(edge_directions_, a - c, false);
  }
  UpdateBounds();
}

void ConvexPiece::UpdateBounds() {
  lo_ = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  hi_ = -lo_;
  for (const Eigen::Vector3d& v : vertices_) {
    lo_ = lo_.cwiseMin(v);
    hi_ = hi_.cwiseMax(v);
  }
}

ConvexPiece ConvexPiece::Placed(const Pose3& frame_from_piece) const {
  ConvexPiece out;
  for (const Eigen::Vector3d& v : vertices_) out.vertices_.push_back(frame_from_piece * v);
  for (const Eigen::Vector3d& n : face_normals_) out.face_normals_.push_back(frame_from_piece.linear() * n);
  for (const Eigen::Vector3d& e : edge_directions_) out.edge_directions_.push_back(frame_from_piece.linear() * e);
  out.UpdateBounds();
  return out;
}

bool ConvexPiece::MeetsTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) const {
  const Eigen::Vector3d tri_lo = a.cwiseMin(b).cwiseMin(c), tri_hi = a.cwiseMax(b).cwiseMax(c);
  if ((tri_lo.array() > hi_.array()).any() || (tri_hi.array() < lo_.array()).any()) return false;
  const std::array<Eigen::Vector3d, 3> corners{a, b, c};
  const auto separated = [&](const Eigen::Vector3d& axis) {
    if (axis.squaredNorm() < 1e-30) return false;
    double piece_min = std::numeric_limits<double>::infinity(), piece_max = -piece_min;
    for (const Eigen::Vector3d& v : vertices_) {
      const double p = v.dot(axis);
      piece_min = std::min(piece_min, p);
      piece_max = std::max(piece_max, p);
    }
    const double t0 = a.dot(axis), t1 = b.dot(axis), t2 = c.dot(axis);
    return std::min({t0, t1, t2}) > piece_max || std::max({t0, t1, t2}) < piece_min;
  };
  for (const Eigen::Vector3d& n : face_normals_) {
    if (separated(n)) return false;
  }
  if (separated((b - a).cross(c - a))) return false;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d edge = corners[(k + 1) % 3] - corners[k];
    for (const Eigen::Vector3d& e : edge_directions_) {
      if (separated(e.cross(edge))) return false;
    }
  }
  return true;
}

bool ConvexPiece::MeetsMesh(const TriangleMesh& mesh) const {
  for (const auto& t : mesh.triangles) {
    if (MeetsTriangle(mesh.vertices[t[0]].cast<double>(), mesh.vertices[t[1]].cast<double>(),
                      mesh.vertices[t[2]].cast<double>())) {
      return true;
    }
  }
  return false;
}

}  // namespace vscan::grasping
