#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "grasping/grasp_kinds.h"
#include "grasping/mesh_rays.h"

namespace vscan::grasping {
namespace {

constexpr double kDegrees = 180 / std::numbers::pi;
// Rays start on their own triangle: hits nearer than this are that triangle.
constexpr double kSelfHitM = 1e-7;

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * kDegrees;
}

// For each approach angle, whether the finger at `contact` (pushing along -outward) would meet a
// sample of the part: the pad (finger_width across, finger_depth along the approach) swept from the
// open jaw to the contact, beyond a clearance from the contact's tangent plane.
std::vector<char> FingerHits(const SurfaceSamples& dense, const SampleGrid& grid, const Eigen::Vector3d& contact,
                             const Eigen::Vector3d& outward, const std::vector<Eigen::Vector3d>& approaches,
                             const ParallelJaws& jaws, double opening, double clearance) {
  std::vector<char> hit(approaches.size(), 0);
  const double sweep = std::max(2 * clearance, (jaws.max_opening_m - opening) / 2);
  const double half_w = jaws.finger_width_m / 2, half_d = jaws.finger_depth_m / 2;
  const double reach = std::sqrt(half_w * half_w + half_d * half_d + sweep * sweep);
  grid.VisitBox(contact.array() - reach, contact.array() + reach, [&](uint32_t i) {
    const Eigen::Vector3d d = dense.points[i] - contact;
    const double along = d.dot(outward);
    if (along <= clearance || along > sweep) return;
    for (size_t k = 0; k < approaches.size(); ++k) {
      if (hit[k]) continue;
      const double z = d.dot(approaches[k]);
      const double x = d.dot(outward.cross(approaches[k]));
      if (std::abs(z) <= half_d && std::abs(x) <= half_w) hit[k] = 1;
    }
  });
  return hit;
}

}  // namespace

std::vector<Grasp> JawGrasps(const TriangleMesh& mesh, const SurfaceSamples& dense, const SurfaceSamples& candidates,
                             const ParallelJaws& jaws, const GraspOptions& options) {
  const MeshRays rays(mesh);
  const double spacing = std::sqrt(dense.area / double(dense.points.size()));
  const SampleGrid grid(dense.points, std::max({jaws.finger_width_m, jaws.finger_depth_m, spacing}));
  const size_t approach_count = options.approaches_per_pair;
  std::vector<std::vector<Grasp>> found(candidates.points.size());
  tbb::parallel_for(size_t(0), candidates.points.size(), [&](size_t i) {
    const Eigen::Vector3d& p = candidates.points[i];
    const Eigen::Vector3d& n = candidates.normals[i];
    const auto exit = rays.FirstHit(p, -n, kSelfHitM, jaws.max_opening_m);
    if (!exit) return;
    const double opening = exit->distance;
    if (opening < jaws.min_opening_m || opening > jaws.max_opening_m) return;
    if (exit->normal.dot(-n) <= 0) return;  // entering the part again: an open or inside-out mesh
    const Eigen::Vector3d q = p - n * opening;
    const Eigen::Vector3d axis = -n;  // from p to q
    // Each contact normal (outward) against the line of the squeeze pushing into it.
    const double angle_p = AngleDeg(n, -axis), angle_q = AngleDeg(exit->normal, axis);
    const double worst = std::max(angle_p, angle_q);
    if (worst > jaws.max_friction_angle_deg) return;
    Eigen::Vector3d u, v;
    PerpendicularBasis(axis, u, v);
    std::vector<Eigen::Vector3d> approaches(approach_count);
    for (size_t k = 0; k < approach_count; ++k) {
      const double theta = 2 * std::numbers::pi * double(k) / double(approach_count);
      approaches[k] = std::cos(theta) * u + std::sin(theta) * v;
    }
    // Within this of a contact's tangent plane a sample is the contact face itself.
    const double clearance = std::max(0.0005, 0.02 * opening);
    const auto hits_p = FingerHits(dense, grid, p, n, approaches, jaws, opening, clearance);
    const auto hits_q = FingerHits(dense, grid, q, axis, approaches, jaws, opening, clearance);
    const double quality = 1 - worst / jaws.max_friction_angle_deg;
    for (size_t k = 0; k < approach_count; ++k) {
      if (hits_p[k] || hits_q[k]) continue;
      Grasp g;
      g.approach = approaches[k];
      g.part_from_tool.linear().col(0) = axis.cross(approaches[k]);
      g.part_from_tool.linear().col(1) = axis;
      g.part_from_tool.linear().col(2) = approaches[k];
      g.part_from_tool.translation() = (p + q) / 2;
      g.quality = std::clamp(quality, 0.0, 1.0);
      g.opening_m = opening;
      found[i].push_back(g);
    }
  });
  std::vector<Grasp> out;
  for (auto& list : found) out.insert(out.end(), list.begin(), list.end());
  return out;
}

}  // namespace vscan::grasping
