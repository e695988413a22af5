#pragma once
// A robot cell emptying a bin, step by step, on a pile held in memory: perceive (the caller's
// scan and localizer), plan on the estimates (grasping::CheckPicks), pick against the true pile
// (the gripper's way in, then whether the grasp holds the part that is really there), take the
// part out and let the pile settle again (physics::SettlePile). See docs/GRASPING.md "Emptying a bin".

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "grasping/grasp_generation.h"
#include "grasping/pick_checks.h"
#include "physics/bin_fill.h"
#include "vscan/common/pose.h"
#include "vscan/common/status.h"

namespace vscan::picking {

// A part found by perception: its type (index into the part types) and pose.
struct Estimate {
  size_t type = 0;
  Pose3 world_from_part = Pose3::Identity();
  double score = 0;  // higher is surer; the plan takes the surest pickable estimate
};

// Sees the pile (the true parts, as a scan would) and returns what the localizer finds.
using Perceive = std::function<StatusOr<std::vector<Estimate>>(const std::vector<physics::PlacedPart>& pile)>;

enum class StepOutcome {
  kPicked,
  kNothingFound,      // no estimate
  kNothingPickable,   // estimates, none pickable by the plan
  kCollision,         // the gripper's way in meets a part or the bin where they truly lie
  kWrongPose,         // the grasp holds no part where it truly lies
};

const char* StepOutcomeName(StepOutcome outcome);

struct PickStep {
  size_t step = 0;
  size_t parts_before = 0;
  size_t estimates = 0;
  size_t pickable_estimates = 0;
  StepOutcome outcome = StepOutcome::kNothingFound;
  std::string detail;
  std::optional<physics::PlacedPart> picked;  // the true part taken (its type and instance)
  Pose3 world_from_tool = Pose3::Identity();  // the planned tool pose, when a pick was tried
  size_t fell_out = 0;                        // parts that left the bin while the pile settled
  double perceive_s = 0, plan_s = 0, settle_s = 0;
};

struct EmptyBinOptions {
  size_t max_steps = 500;
  // The cell gives up after this many failed picks in a row.
  size_t max_failures_in_a_row = 3;
  // A planned tool pose within this distance (and 10 degrees) of one that failed is not tried again.
  double retry_distance_m = 0.005;
};

struct EmptyBinResult {
  std::vector<PickStep> steps;
  std::vector<physics::PlacedPart> pile;  // what is left in the bin
  size_t picked = 0;
  size_t fell_out = 0;
  std::string end;  // "empty", "nothing found", "nothing pickable", "failures in a row", "step bound", "cancelled"
};

struct Cell {
  physics::BinSpec bin;
  std::vector<physics::PartType> types;               // meshes in the part frame, metres
  std::vector<std::vector<grasping::Grasp>> grasps;   // per type, part frame, best first
  std::vector<grasping::PlacedMesh> fixtures;         // besides the bin (which is added)
  grasping::Gripper gripper;
  grasping::PickOptions pick_options;
  grasping::ReachCheck reach;  // empty: every clear grasp is reachable
  physics::FillOptions physics;
};

// INVALID_ARGUMENT for a bad cell (its grasps, gripper, options, bin or part types, named as the
// engine names them) or a pile part of an unknown type; errors of perceive and reach as they are.
// on_step (may be empty) is called after each step with the pile after it.
StatusOr<EmptyBinResult> EmptyBin(const Cell& cell, std::vector<physics::PlacedPart> pile, const Perceive& perceive,
                                  const EmptyBinOptions& options, const std::atomic<bool>* cancel = nullptr,
                                  const std::function<void(const PickStep&, const std::vector<physics::PlacedPart>&)>&
                                      on_step = {});

}  // namespace vscan::picking
