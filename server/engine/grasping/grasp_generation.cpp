#include "grasping/grasp_generation.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include <Eigen/Geometry>

#include "grasping/grasp_kinds.h"
#include "random/seeded_draws.h"

namespace vscan::grasping {
namespace {

// Parts larger than this are not parts.
constexpr double kMaxPartExtentM = 100;
// Worst-case checks (a candidate against every sample or triangle) one call may cost: a few seconds.
constexpr double kMaxWork = 2e9;
// Keys separating the candidate draws from the dense samples.
constexpr uint64_t kDenseKey = 0x6772617370ull, kCandidateKey = 0x63616e64ull;

}  // namespace

Status ValidateGraspOptions(const GraspOptions& o) {
  if (o.max_grasps < 1 || o.max_grasps > 100000) return InvalidArgument("grasp_options.max_grasps", "must be in [1, 100000]");
  if (o.surface_samples < 100 || o.surface_samples > 2000000) {
    return InvalidArgument("grasp_options.surface_samples", "must be in [100, 2000000]");
  }
  if (o.candidates < 1 || o.candidates > 100000) return InvalidArgument("grasp_options.candidates", "must be in [1, 100000]");
  if (o.approaches_per_pair < 1 || o.approaches_per_pair > 64) {
    return InvalidArgument("grasp_options.approaches_per_pair", "must be in [1, 64]");
  }
  if (!std::isfinite(o.flatness_tolerance_m) || o.flatness_tolerance_m <= 0 || o.flatness_tolerance_m > 0.01) {
    return InvalidArgument("grasp_options.flatness_tolerance_m", "must be in (0, 0.01] m");
  }
  return Status::Ok();
}

namespace {

}  // namespace

Status CheckGraspWork(size_t triangles, const Gripper& gripper, const GraspOptions& o) {
  // Each candidate may visit every dense sample (suction; jaws: at both contacts, for every
  // approach) and, for jaws, test every triangle.
  const bool jaws = std::holds_alternative<ParallelJaws>(gripper);
  const double per_candidate = jaws ? double(triangles) + 2.0 * double(o.surface_samples) * double(o.approaches_per_pair)
                                    : double(o.surface_samples);
  if (double(o.candidates) * per_candidate > kMaxWork) {
    return ResourceExhausted("grasp_options.candidates",
                             jaws ? "candidates x (triangles + 2 x surface_samples x approaches_per_pair) must be <= 2e9"
                                  : "candidates x surface_samples must be <= 2e9");
  }
  return Status::Ok();
}

Status ValidatePartMesh(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return InvalidArgument("mesh", "has no triangles");
  for (const auto& v : mesh.vertices) {
    if (!v.allFinite()) return InvalidArgument("mesh", "has a non-finite vertex");
  }
  for (const auto& t : mesh.triangles) {
    for (uint32_t i : t) {
      if (i >= mesh.vertices.size()) return InvalidArgument("mesh", "has a triangle index out of range");
    }
  }
  Eigen::Vector3f lo, hi;
  mesh.Bounds(lo, hi);
  if (!((hi - lo).cast<double>().maxCoeff() <= kMaxPartExtentM)) {
    return InvalidArgument("mesh", "is larger than 100 m (are its units metres?)");
  }
  return Status::Ok();
}

void PerpendicularBasis(const Eigen::Vector3d& z, Eigen::Vector3d& x, Eigen::Vector3d& y) {
  // Start from the world axis least aligned with z, so the result is stable and well conditioned.
  Eigen::Index smallest;
  z.cwiseAbs().minCoeff(&smallest);
  x = Eigen::Vector3d::Unit(smallest).cross(z).normalized();
  y = z.cross(x);
}

StatusOr<std::vector<Grasp>> GenerateGrasps(const TriangleMesh& mesh, const Gripper& gripper,
                                            const GraspOptions& options) {
  if (auto s = ValidateGripper(gripper); !s.ok()) return s;
  if (auto s = ValidateGraspOptions(options); !s.ok()) return s;
  if (auto s = ValidatePartMesh(mesh); !s.ok()) return s;
  if (auto s = CheckGraspWork(mesh.triangles.size(), gripper, options); !s.ok()) return s;
  const SurfaceSamples dense = SampleSurface(mesh, options.surface_samples, options.seed ^ kDenseKey);
  if (!(dense.area > 0) || !std::isfinite(dense.area)) return InvalidArgument("mesh", "has no surface area");
  const SurfaceSamples candidates =
      SampleSurface(mesh, options.candidates, random::SplitMix64(options.seed) ^ kCandidateKey);
  std::vector<Grasp> grasps;
  if (const auto* cup = std::get_if<SuctionCup>(&gripper)) {
    grasps = SuctionGrasps(dense, candidates, *cup, options);
  } else {
    grasps = JawGrasps(mesh, dense, candidates, std::get<ParallelJaws>(gripper), options);
  }
  // Qualities equal but for rounding (the same flatness on two parallel faces) tie, and ties keep
  // the draw order, so that the best grasps are not all on one face.
  for (Grasp& g : grasps) g.quality = std::round(g.quality * 1e9) / 1e9;
  std::stable_sort(grasps.begin(), grasps.end(), [](const Grasp& a, const Grasp& b) { return a.quality > b.quality; });
  if (grasps.size() > options.max_grasps) grasps.resize(options.max_grasps);
  return grasps;
}

}  // namespace vscan::grasping
