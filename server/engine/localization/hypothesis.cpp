#include "localization/hypothesis.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "registration/point_to_plane_icp.h"
#include "spatial/kd_tree.h"

namespace vscan::localization {
namespace {

// The most scan points a candidate's ICP runs on.
constexpr size_t kMaxIcpPoints = 2000;

}  // namespace

Verifier::Verifier(const PartModel& part, const ScanGrid& grid, const PreparedScan& scan, const LocalizerOptions& options)
    : part_(part), grid_(grid), scan_(scan), options_(options),
      min_cos_(std::cos(options.max_normal_angle_deg * std::numbers::pi / 180)) {}

StatusOr<Hypothesis> Verifier::Verify(const Pose3& voted) const {
  const double wide = kIcpReachInPpfSteps * part_.ppf_step;
  const double tight = options_.explained_distance_voxels * part_.voxel;
  ASSIGN_OR_RETURN(const Pose3 coarse, Refine(voted, wide));
  ASSIGN_OR_RETURN(const Pose3 refined, Refine(coarse, tight));
  Hypothesis h;
  h.pose = refined;
  h.explained = Near(refined, tight, min_cos_);
  h.score = ExplainedShare(refined, h.explained);
  if (scan_.view) h.view = scan_.view->Check(part_.model, refined, tight);
  if (scan_.support) h.below_support = BelowSupport(refined, tight);
  return h;
}

// The prepared scan points within reach of the placed part's surface (and, with min_cos > -1,
// facing as it does there).
std::vector<uint32_t> Verifier::Near(const Pose3& world_from_part, double reach, double min_cos) const {
  std::vector<Eigen::Vector3f> placed(part_.ppf_points.points.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    placed[i] = (world_from_part * part_.ppf_points.points[i].cast<double>()).cast<float>();
  }
  std::vector<uint32_t> gathered;
  grid_.Gather(placed, gathered);
  const Eigen::Isometry3f part_from_world = world_from_part.inverse().cast<float>();
  const auto max_sq = static_cast<float>(reach * reach);
  std::array<spatial::Neighbor, 1> nearest{};
  std::vector<uint32_t> near;
  const Eigen::AlignedBox3f reach_box(part_.bounds.min().array() - static_cast<float>(reach),
                                      part_.bounds.max().array() + static_cast<float>(reach));
  for (const uint32_t i : gathered) {
    const Eigen::Vector3f local = part_from_world * scan_.points.points[i];
    if (!reach_box.contains(local) || part_.model_tree->Knn(local, max_sq, nearest) == 0) continue;
    if (min_cos > -1) {
      const Eigen::Vector3f& normal = part_.model.normals[part_.model_tree->original_index(nearest[0].slot)];
      if (normal.dot(part_from_world.linear() * scan_.points.normals[i]) < min_cos) continue;
    }
    near.push_back(i);
  }
  std::sort(near.begin(), near.end());
  return near;
}

// The share of the part's points, placed, farther than depth behind the support plane.
double Verifier::BelowSupport(const Pose3& world_from_part, double depth) const {
  size_t below = 0;
  for (const auto& p : part_.model.points) {
    const Eigen::Vector3d world = world_from_part * p.cast<double>();
    below += scan_.support->normal.dot(world) + scan_.support->offset < -depth ? 1 : 0;
  }
  return static_cast<double>(below) / static_cast<double>(std::max<size_t>(1, part_.model.points.size()));
}

// Point-to-plane ICP of the scan points within reach of the part placed at start onto the part's
// surface. A degenerate stop keeps the pose reached so far: the directions the view leaves free
// (a face seen alone can slide within itself) stay as voted, the others are refined.
StatusOr<Pose3> Verifier::Refine(const Pose3& start, double reach) const {
  const std::vector<uint32_t> near = Near(start, reach, -1);
  registration::IcpOptions icp;
  icp.max_correspondence_distance = reach;
  // A hundredth of a millimetre and a tenth of a milliradian are finer than any check after it.
  icp.translation_tolerance = 1e-5;
  icp.rotation_tolerance = 1e-4;
  icp.max_iterations = 30;
  if (near.size() < icp.min_correspondences) return start;
  // An even share of the points is enough to pull a pose within reach onto the surface.
  const size_t stride = (near.size() + kMaxIcpPoints - 1) / kMaxIcpPoints;
  std::vector<Eigen::Vector3f> points, normals;
  points.reserve(near.size() / stride + 1);
  normals.reserve(near.size() / stride + 1);
  for (size_t k = 0; k < near.size(); k += stride) {
    points.push_back(scan_.points.points[near[k]]);
    normals.push_back(scan_.points.normals[near[k]]);
  }
  ASSIGN_OR_RETURN(const registration::IcpResult fit,
                   registration::PointToPlaneIcp(points, *part_.icp_target, start.inverse(), icp, normals));
  return fit.stop == registration::IcpStop::kTooFewCorrespondences ? start : fit.target_from_source.inverse();
}

// The share of the part's points, placed, with an explained scan point within the inlier
// distance whose normal is within max_normal_angle_deg of the part's there.
double Verifier::ExplainedShare(const Pose3& world_from_part, const std::vector<uint32_t>& explained) const {
  if (explained.empty()) return 0;
  const Eigen::Isometry3f part_from_world = world_from_part.inverse().cast<float>();
  std::vector<Eigen::Vector3f> local(explained.size());
  for (size_t k = 0; k < explained.size(); ++k) local[k] = part_from_world * scan_.points.points[explained[k]];
  const spatial::KdTree tree(local);
  const double distance = options_.inlier_distance_voxels * part_.voxel;
  const auto max_sq = static_cast<float>(distance * distance);
  std::array<spatial::Neighbor, 1> nearest{};
  size_t inliers = 0;
  for (size_t i = 0; i < part_.model.points.size(); ++i) {
    if (tree.Knn(part_.model.points[i], max_sq, nearest) == 0) continue;
    const Eigen::Vector3f normal =
        part_from_world.linear() * scan_.points.normals[explained[tree.original_index(nearest[0].slot)]];
    if (part_.model.normals[i].dot(normal) >= min_cos_) ++inliers;
  }
  return static_cast<double>(inliers) / static_cast<double>(part_.model.points.size());
}

}  // namespace vscan::localization
