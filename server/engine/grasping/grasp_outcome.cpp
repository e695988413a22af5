#include "grasping/grasp_outcome.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "grasping/grasp_kinds.h"

namespace vscan::grasping {
namespace {

constexpr double kToRadians = std::numbers::pi / 180;
// Keys the dense samples apart from grasp generation's draws.
constexpr uint64_t kOutcomeSamplesKey = 0x6f7574636f6d65ull;

}  // namespace

GraspTarget::GraspTarget(const TriangleMesh& mesh, const Gripper& gripper, const OutcomeOptions& options)
    : gripper_(gripper), options_(options), rays_(mesh),
      dense_(SampleSurface(mesh, options.surface_samples, options.seed ^ kOutcomeSamplesKey)) {
  if (const auto* cup = std::get_if<SuctionCup>(&gripper)) {
    const double spacing = std::sqrt(dense_.area / double(dense_.points.size()));
    grid_ = std::make_unique<SampleGrid>(dense_.points, std::max(cup->diameter_m / 2, spacing));
    disc_ = std::make_unique<DiscCells>(DiscCellsFor(dense_, *cup));
  }
}

StatusOr<std::shared_ptr<const GraspTarget>> GraspTarget::Make(const TriangleMesh& mesh, const Gripper& gripper,
                                                               const OutcomeOptions& options) {
  RETURN_IF_ERROR(ValidateGripper(gripper));
  RETURN_IF_ERROR(ValidatePartMesh(mesh));
  if (options.surface_samples < 100 || options.surface_samples > 2000000) {
    return InvalidArgument("outcome_options.surface_samples", "must be in [100, 2000000]");
  }
  if (!std::isfinite(options.overtravel_m) || options.overtravel_m < 0 || options.overtravel_m > 1) {
    return InvalidArgument("outcome_options.overtravel_m", "must be in [0, 1] m");
  }
  if (!std::isfinite(options.flatness_tolerance_m) || options.flatness_tolerance_m <= 0 ||
      options.flatness_tolerance_m > 0.01) {
    return InvalidArgument("outcome_options.flatness_tolerance_m", "must be in (0, 0.01] m");
  }
  auto target = std::shared_ptr<GraspTarget>(new GraspTarget(mesh, gripper, options));
  if (!(target->dense_.area > 0) || !std::isfinite(target->dense_.area)) {
    return InvalidArgument("mesh", "has no surface area");
  }
  return std::shared_ptr<const GraspTarget>(std::move(target));
}

GraspOutcome GraspTarget::Try(const Grasp& grasp, const Pose3& truth_from_estimate) const {
  const Pose3 truth_from_tool = truth_from_estimate * grasp.part_from_tool;
  if (!truth_from_tool.matrix().allFinite()) return {false, "the pose is not finite", 0};
  if (const auto* cup = std::get_if<SuctionCup>(&gripper_)) return TrySuction(*cup, truth_from_tool);
  return TryJaws(std::get<ParallelJaws>(gripper_), truth_from_tool);
}

GraspOutcome GraspTarget::TrySuction(const SuctionCup& cup, const Pose3& truth_from_tool) const {
  const Eigen::Vector3d contact = truth_from_tool.translation();
  const Eigen::Vector3d axis = truth_from_tool.linear().col(2).normalized();
  const Eigen::Vector3d start = contact - axis * cup.stroke_m;
  const auto hit = rays_.FirstHit(start, axis, 0, cup.stroke_m + options_.overtravel_m);
  if (!hit) return {false, "the cup meets no surface of the part", 0};
  GraspOutcome out;
  out.contact_offset_m = hit->distance - cup.stroke_m;
  if (hit->normal.dot(-axis) <= 0) {
    out.why = "the cup starts inside the part";
    return out;
  }
  if (hit->normal.dot(-axis) < std::cos(cup.max_tilt_deg * kToRadians)) {
    out.why = "the surface tilts more than the cup allows";
    return out;
  }
  const SealCheck seal =
      CheckSeal(dense_, *grid_, *disc_, start + axis * hit->distance, hit->normal, cup, options_.flatness_tolerance_m);
  if (!seal.sealed) {
    out.why = "the cup does not seal (an edge, a hole or curvature under it)";
    return out;
  }
  out.holds = true;
  return out;
}

GraspOutcome GraspTarget::TryJaws(const ParallelJaws& jaws, const Pose3& truth_from_tool) const {
  const Eigen::Vector3d centre = truth_from_tool.translation();
  const Eigen::Vector3d closing = truth_from_tool.linear().col(1).normalized();
  const double half_open = jaws.max_opening_m / 2;
  const double cos_cone = std::cos(jaws.max_friction_angle_deg * kToRadians);
  GraspOutcome out;
  double travelled = 0;
  for (double side : {1.0, -1.0}) {
    const Eigen::Vector3d direction = -side * closing;  // from the open finger towards the centre
    const auto hit = rays_.FirstHit(centre - direction * half_open, direction, 0, jaws.max_opening_m);
    if (!hit) {
      out.why = "a finger closes on nothing";
      return out;
    }
    if (hit->normal.dot(-direction) <= 0) {
      out.why = "a finger lands on the part";
      return out;
    }
    if (hit->normal.dot(-direction) < cos_cone) {
      out.why = "a contact lies outside the friction cone";
      return out;
    }
    travelled += hit->distance;
  }
  out.contact_offset_m = jaws.max_opening_m - travelled;
  if (out.contact_offset_m < jaws.min_opening_m - options_.flatness_tolerance_m) {
    out.why = "the fingers close narrower than the jaws' minimum opening";
    return out;
  }
  out.holds = true;
  return out;
}

}  // namespace vscan::grasping
