#pragma once
// Which parts of a settled pile a gripper on a robot can pick: for every part, its grasps (part
// frame) tried best first until one passes every check. See docs/GRASPING.md "Picks".

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "grasping/grasp_generation.h"
#include "grasping/gripper_sweep.h"
#include "grasping/sweep_contact.h"
#include "vscan/common/mesh.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::grasping {

// A mesh placed in the world: world_point = world_from_mesh * mesh_point (metres).
struct PlacedMesh {
  std::shared_ptr<const TriangleMesh> mesh;
  Pose3 world_from_mesh = Pose3::Identity();
};

struct PilePart {
  size_t type = 0;  // index into the grasps given to CheckPicks
  std::shared_ptr<const TriangleMesh> mesh;  // metres, part frame
  Pose3 world_from_part = Pose3::Identity();
};

struct Pile {
  std::vector<PilePart> parts;
  // What is not picked but may be hit: the bin, the floor, fixtures (world frame after the pose).
  std::vector<PlacedMesh> fixtures;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();  // against gravity, unit
};

// Why a part cannot be picked: the furthest check any of its grasps reached.
enum class PickFailure {
  kNone,               // pickable
  kCovered,            // another part (or a fixture) lies on its upward faces
  kNoGrasp,            // no grasp of its type, or none whose approach comes from above within the tilt
  kGripperCollision,   // every remaining grasp's gripper sweep meets the bin or another part
  kUnreachable,        // no collision-free grasp is reachable by the arm (grasp and pre-grasp)
  kArmCollision,       // reachable, but the arm then touches something
};

const char* PickFailureName(PickFailure failure);

struct PickOptions {
  ToolSweep sweep;
  // The approach may tilt this far from straight down (-up), degrees in [0, 180].
  double max_approach_tilt_deg = 60;
  // A part is covered when another part or a fixture lies within this distance straight above its
  // upward faces (faces within 70 degrees of up).
  double cover_distance_m = 0.002;
  size_t cover_samples = 400;  // surface samples per part type for the cover test, [10, 100000]
  // Grasps per part sent to the reach check, best first, at most [1, 1000].
  size_t max_reach_checks = 8;
  uint64_t seed = 1;
};

// INVALID_ARGUMENT naming "pick_options.*" for a value out of its range.
Status ValidatePickOptions(const PickOptions& options);

// The arm's answer for one grasp: the tool (centre point, z along the approach) at
// world_from_tool and, before it, at world_from_pregrasp.
struct ReachAnswer {
  PickFailure failure = PickFailure::kNone;  // kNone, kUnreachable or kArmCollision
  std::string detail;                        // what missed or what the arm touches
  Eigen::VectorXd joint_positions;           // at the grasp, when reached
};
using ReachCheck = std::function<StatusOr<ReachAnswer>(const Pose3& world_from_tool, const Pose3& world_from_pregrasp)>;

// Something of the pile a check met: another part or a fixture, by its index.
struct PileItem {
  bool fixture = false;
  size_t index = 0;
  bool operator==(const PileItem&) const = default;
};
std::string Describe(const PileItem& item);  // "part 3", "fixture 0"

struct PickVerdict {
  bool pickable = false;
  PickFailure failure = PickFailure::kNone;
  std::string detail;
  std::optional<size_t> grasp;  // the index into its type's grasps that passed
  Pose3 world_from_tool = Pose3::Identity();
  Eigen::VectorXd joint_positions;
  std::optional<PileItem> covered_by;  // kCovered: what lies on it
  std::optional<PileItem> blocked_by;  // kGripperCollision: what the best grasp's sweep meets first
  // Grasps that got past each check: approach within the tilt, gripper sweep clear, sent to the arm.
  size_t grasps_from_above = 0;
  size_t grasps_clear = 0;
  size_t reach_checks = 0;
};

// The most gripper sweeps one CheckPicks tests: every grasp of every part together.
inline constexpr double kMaxSweepChecks = 1e6;

// One verdict per pile part, in order. grasps_per_type[t] are part-frame grasps (best first) of
// type t; reach may be empty (no arm: every clear grasp counts as reached) and is called from
// several threads at once. INVALID_ARGUMENT names "pile.parts[i]" (missing mesh, type out of
// range, non-finite pose), "pile.fixtures[i]", "pick_options.*" or the gripper's field; errors of
// reach are returned as they are; RESOURCE_EXHAUSTED naming "grasp_options.max_grasps" when the
// parts' grasps together exceed 1e6. CANCELLED once *cancel is set.
StatusOr<std::vector<PickVerdict>> CheckPicks(const Pile& pile, std::span<const std::vector<Grasp>> grasps_per_type,
                                              const Gripper& gripper, const PickOptions& options,
                                              const ReachCheck& reach, const std::atomic<bool>* cancel = nullptr);

// The gripper's sweep (pieces in the tool frame, GripperSweep) placed at a grasp against every
// fixture and every part but the grasped one, exactly (sweep_contact.h): the first contact
// (fixtures first), or empty when clear.
std::optional<PileItem> FindSweepContact(const Pile& pile, size_t grasped, std::span<const ConvexPiece> sweep,
                                         const Pose3& world_from_tool);

}  // namespace vscan::grasping
