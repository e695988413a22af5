#include "grasping/pick_checks.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <Eigen/Geometry>
#include <tbb/parallel_for.h>

#include "grasping/mesh_rays.h"
#include "grasping/surface_samples.h"

namespace vscan::grasping {
namespace {

// Gripper sweeps one check may test at worst (each some tens to hundreds of microseconds).
// Faces within 70 degrees of up can carry another part.
const double kUpwardCos = std::cos(70 * std::numbers::pi / 180);
// A ray from a part's own face meets the part itself only beyond kOwnFaceM (nearer is that face);
// parts are smaller than kOwnCeilingM.
constexpr double kOwnFaceM = 1e-7;
constexpr double kOwnCeilingM = 10.0;
// Cover rays start this far inside the part, so a neighbour resting slightly into it still counts.
constexpr double kCoverStartDepthM = 0.001;

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  void Add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool Overlaps(const Box& o) const { return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all(); }
};

Box WorldBox(const TriangleMesh& mesh, const Pose3& world_from_mesh) {
  Box box;
  for (const Eigen::Vector3f& v : mesh.vertices) box.Add(world_from_mesh * v.cast<double>());
  return box;
}

// Per distinct mesh: rays for the cover test and samples of its surface.
struct MeshData {
  std::unique_ptr<MeshRays> rays;
  SurfaceSamples samples;
};

}  // namespace

Status ValidatePickOptions(const PickOptions& o) {
  const auto bad = [](double v, double lo, double hi) { return !std::isfinite(v) || v < lo || v > hi; };
  if (bad(o.sweep.body_length_m, 0, 10)) return InvalidArgument("pick_options.body_length_m", "must be in [0, 10] m");
  if (bad(o.sweep.approach_m, 0, 10)) return InvalidArgument("pick_options.approach_m", "must be in [0, 10] m");
  if (bad(o.max_approach_tilt_deg, 0, 180)) {
    return InvalidArgument("pick_options.max_approach_tilt_deg", "must be in [0, 180] degrees");
  }
  if (bad(o.cover_distance_m, 0, 1)) return InvalidArgument("pick_options.cover_distance_m", "must be in [0, 1] m");
  if (o.cover_samples < 10 || o.cover_samples > 100000) {
    return InvalidArgument("pick_options.cover_samples", "must be in [10, 100000]");
  }
  if (o.max_reach_checks < 1 || o.max_reach_checks > 1000) {
    return InvalidArgument("pick_options.max_reach_checks", "must be in [1, 1000]");
  }
  return Status::Ok();
}

namespace {

Status CheckMesh(const std::shared_ptr<const TriangleMesh>& mesh, const std::string& field) {
  if (mesh == nullptr || mesh->empty()) return InvalidArgument(field, "is missing or empty");
  for (const Eigen::Vector3f& v : mesh->vertices) {
    if (!v.allFinite()) return InvalidArgument(field, "has a non-finite vertex");
  }
  for (const auto& t : mesh->triangles) {
    if (t[0] >= mesh->vertices.size() || t[1] >= mesh->vertices.size() || t[2] >= mesh->vertices.size()) {
      return InvalidArgument(field, "has a triangle index out of range");
    }
  }
  return Status::Ok();
}

Status ValidatePile(const Pile& pile, size_t types) {
  if (!pile.up.allFinite() || pile.up.norm() < 1e-9) return InvalidArgument("pile.up", "must be a finite non-zero direction");
  for (size_t i = 0; i < pile.parts.size(); ++i) {
    const PilePart& part = pile.parts[i];
    const std::string field = "pile.parts[" + std::to_string(i) + "]";
    RETURN_IF_ERROR(CheckMesh(part.mesh, field + ".mesh"));
    if (part.type >= types) return InvalidArgument(field + ".type", "has no grasps given for it");
    if (!part.world_from_part.matrix().allFinite()) return InvalidArgument(field + ".pose", "is not finite");
  }
  for (size_t f = 0; f < pile.fixtures.size(); ++f) {
    const PlacedMesh& fixture = pile.fixtures[f];
    const std::string field = "pile.fixtures[" + std::to_string(f) + "]";
    RETURN_IF_ERROR(CheckMesh(fixture.mesh, field + ".mesh"));
    if (!fixture.world_from_mesh.matrix().allFinite()) return InvalidArgument(field + ".pose", "is not finite");
  }
  return Status::Ok();
}

int Rank(PickFailure f) {
  switch (f) {
    case PickFailure::kNoGrasp: return 0;
    case PickFailure::kGripperCollision: return 1;
    case PickFailure::kUnreachable: return 2;
    case PickFailure::kArmCollision: return 3;
    default: return -1;
  }
}

void Note(PickVerdict& verdict, PickFailure failure, const std::string& detail,
          std::optional<PileItem> blocked_by = std::nullopt) {
  if (Rank(failure) > Rank(verdict.failure)) {
    verdict.failure = failure;
    verdict.detail = detail;
    verdict.blocked_by = blocked_by;
  }
}

// The world bounds of every fixture and part, computed once for all the sweeps of a check.
struct PileBounds {
  std::vector<Box> fixtures;
  std::vector<Box> parts;
};

PileBounds BoundsOf(const Pile& pile) {
  PileBounds bounds;
  for (const PlacedMesh& fixture : pile.fixtures) bounds.fixtures.push_back(WorldBox(*fixture.mesh, fixture.world_from_mesh));
  for (const PilePart& part : pile.parts) bounds.parts.push_back(WorldBox(*part.mesh, part.world_from_part));
  return bounds;
}

std::optional<PileItem> SweepContact(const Pile& pile, const PileBounds& bounds, size_t grasped,
                                     std::span<const ConvexPiece> sweep, const Pose3& world_from_tool) {
  Box sweep_box;
  for (const ConvexPiece& piece : sweep) {
    const ConvexPiece placed = piece.Placed(world_from_tool);
    sweep_box.Add(placed.lo());
    sweep_box.Add(placed.hi());
  }
  const auto meets = [&](const TriangleMesh& mesh, const Pose3& world_from_mesh, const Box& box) {
    if (!box.Overlaps(sweep_box)) return false;
    const Pose3 mesh_from_tool = world_from_mesh.inverse() * world_from_tool;
    return std::any_of(sweep.begin(), sweep.end(),
                       [&](const ConvexPiece& piece) { return piece.Placed(mesh_from_tool).MeetsMesh(mesh); });
  };
  for (size_t f = 0; f < pile.fixtures.size(); ++f) {
    if (meets(*pile.fixtures[f].mesh, pile.fixtures[f].world_from_mesh, bounds.fixtures[f])) return PileItem{true, f};
  }
  for (size_t j = 0; j < pile.parts.size(); ++j) {
    if (j != grasped && meets(*pile.parts[j].mesh, pile.parts[j].world_from_part, bounds.parts[j])) {
      return PileItem{false, j};
    }
  }
  return std::nullopt;
}

}  // namespace

std::string Describe(const PileItem& item) {
  return (item.fixture ? "fixture " : "part ") + std::to_string(item.index);
}

const char* PickFailureName(PickFailure failure) {
  switch (failure) {
    case PickFailure::kNone: return "none";
    case PickFailure::kCovered: return "covered";
    case PickFailure::kNoGrasp: return "no_grasp";
    case PickFailure::kGripperCollision: return "gripper_collision";
    case PickFailure::kUnreachable: return "unreachable";
    case PickFailure::kArmCollision: return "arm_collision";
  }
  return "unknown";
}

std::optional<PileItem> FindSweepContact(const Pile& pile, size_t grasped, std::span<const ConvexPiece> sweep,
                                         const Pose3& world_from_tool) {
  return SweepContact(pile, BoundsOf(pile), grasped, sweep, world_from_tool);
}

StatusOr<std::vector<PickVerdict>> CheckPicks(const Pile& pile, std::span<const std::vector<Grasp>> grasps_per_type,
                                              const Gripper& gripper, const PickOptions& options,
                                              const ReachCheck& reach, const std::atomic<bool>* cancel) {
  RETURN_IF_ERROR(ValidateGripper(gripper));
  RETURN_IF_ERROR(ValidatePickOptions(options));
  RETURN_IF_ERROR(ValidatePile(pile, grasps_per_type.size()));
  double sweeps = 0;  // the gripper sweeps tested at worst: every grasp of every part
  for (const PilePart& part : pile.parts) sweeps += double(grasps_per_type[part.type].size());
  if (sweeps > kMaxSweepChecks) {
    return ResourceExhausted("grasp_options.max_grasps", "the parts' grasps together (" + std::to_string(size_t(sweeps)) +
                                                             ") must be at most 1e6 in one check");
  }
  const Eigen::Vector3d up = pile.up.normalized();
  const double cos_tilt = std::cos(options.max_approach_tilt_deg * std::numbers::pi / 180);

  std::map<const TriangleMesh*, MeshData> meshes;
  for (const PilePart& part : pile.parts) {
    MeshData& data = meshes[part.mesh.get()];
    if (data.rays) continue;
    data.rays = std::make_unique<MeshRays>(*part.mesh);
    data.samples = SampleSurface(*part.mesh, options.cover_samples, options.seed);
  }
  // What may lie on a part: the other parts and the fixtures.
  struct Above {
    PileItem item;
    const TriangleMesh* mesh;
    Pose3 world_from_mesh;
    Box box;
  };
  const PileBounds bounds = BoundsOf(pile);
  std::vector<Above> above;
  for (size_t j = 0; j < pile.parts.size(); ++j) {
    const PilePart& part = pile.parts[j];
    above.push_back({{false, j}, part.mesh.get(), part.world_from_part, bounds.parts[j]});
  }
  for (size_t f = 0; f < pile.fixtures.size(); ++f) {
    const PlacedMesh& fixture = pile.fixtures[f];
    MeshData& data = meshes[fixture.mesh.get()];
    if (!data.rays) data.rays = std::make_unique<MeshRays>(*fixture.mesh);
    above.push_back({{true, f}, fixture.mesh.get(), fixture.world_from_mesh, bounds.fixtures[f]});
  }
  std::vector<ConvexPiece> sweep;
  for (const TriangleMesh& piece : GripperSweep(gripper, options.sweep)) sweep.emplace_back(piece);

  std::vector<PickVerdict> verdicts(pile.parts.size());
  std::vector<Status> errors(pile.parts.size());
  const auto cancelled = [cancel] { return cancel != nullptr && cancel->load(std::memory_order_relaxed); };
  tbb::parallel_for(size_t(0), pile.parts.size(), [&](size_t i) {
    if (cancelled()) return;
    const PilePart& part = pile.parts[i];
    PickVerdict& verdict = verdicts[i];
    verdict.failure = PickFailure::kNoGrasp;
    verdict.detail = "no grasp of this part's type";

    // Covered: another part or a fixture straight above an upward face, within the cover distance.
    const SurfaceSamples& samples = meshes.at(part.mesh.get()).samples;
    std::vector<size_t> hits(above.size(), 0);
    const MeshRays& own = *meshes.at(part.mesh.get()).rays;
    const Eigen::Vector3d up_in_part = part.world_from_part.linear().transpose() * up;
    for (size_t s = 0; s < samples.points.size(); ++s) {
      if ((part.world_from_part.linear() * samples.normals[s]).dot(up) < kUpwardCos) continue;
      // A face under the part's own material (a bore's floor, a cavity's) carries nothing; its ray,
      // started below a wall thinner than the start depth, would meet what lies under the part.
      if (own.FirstHit(samples.points[s], up_in_part, kOwnFaceM, kOwnCeilingM)) continue;
      const Eigen::Vector3d origin = part.world_from_part * samples.points[s] - up * kCoverStartDepthM;
      const double length = options.cover_distance_m + kCoverStartDepthM;
      Box ray;
      ray.Add(origin);
      ray.Add(origin + up * length);
      for (size_t j = 0; j < above.size(); ++j) {
        if (above[j].item == PileItem{false, i} || !above[j].box.Overlaps(ray)) continue;
        const Pose3 mesh_from_world = above[j].world_from_mesh.inverse();
        const Eigen::Vector3d direction = mesh_from_world.linear() * up;
        const auto hit = meshes.at(above[j].mesh).rays->FirstHit(mesh_from_world * origin, direction, 0, length);
        // Only a face met from below counts: a ray that starts inside a neighbour (a part touching
        // a wall, pressed into it a fraction of a millimetre) leaves it through a face facing up.
        if (hit && hit->normal.dot(direction) < 0) ++hits[j];
      }
    }
    const auto most = std::max_element(hits.begin(), hits.end());
    if (most != hits.end() && *most > 0) {
      verdict.failure = PickFailure::kCovered;
      verdict.covered_by = above[size_t(most - hits.begin())].item;
      verdict.detail = Describe(*verdict.covered_by) + " lies on it";
      return;
    }

    const std::vector<Grasp>& grasps = grasps_per_type[part.type];
    for (size_t g = 0; g < grasps.size() && verdict.reach_checks < options.max_reach_checks && !cancelled(); ++g) {
      const Pose3 world_from_tool = part.world_from_part * grasps[g].part_from_tool;
      if (world_from_tool.linear().col(2).dot(-up) < cos_tilt - 1e-12) continue;
      ++verdict.grasps_from_above;
      if (const auto contact = SweepContact(pile, bounds, i, sweep, world_from_tool)) {
        Note(verdict, PickFailure::kGripperCollision, "the gripper's way in meets " + Describe(*contact), contact);
        continue;
      }
      ++verdict.grasps_clear;
      ReachAnswer answer;
      if (reach) {
        Pose3 tool_from_pregrasp = Pose3::Identity();
        tool_from_pregrasp.translation() = Eigen::Vector3d(0, 0, -options.sweep.approach_m);
        ++verdict.reach_checks;
        auto checked = reach(world_from_tool, world_from_tool * tool_from_pregrasp);
        if (!checked.ok()) {
          errors[i] = checked.status();
          return;
        }
        answer = std::move(*checked);
      }
      if (answer.failure == PickFailure::kNone) {
        verdict.pickable = true;
        verdict.failure = PickFailure::kNone;
        verdict.detail.clear();
        verdict.grasp = g;
        verdict.world_from_tool = world_from_tool;
        verdict.joint_positions = std::move(answer.joint_positions);
        return;
      }
      Note(verdict, answer.failure, answer.detail);
    }
    if (verdict.failure == PickFailure::kNoGrasp && !grasps.empty()) {
      verdict.detail = "no grasp approaches from within " + std::to_string(int(options.max_approach_tilt_deg)) +
                       " degrees of straight down";
    }
  });
  if (cancelled()) return Cancelled("picks: cancelled");
  for (const Status& error : errors) RETURN_IF_ERROR(error);
  return verdicts;
}

}  // namespace vscan::grasping
